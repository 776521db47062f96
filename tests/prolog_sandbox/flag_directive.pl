% expect: set_prolog_flag/2: a mission cannot change Prolog's flags
mission.
:- set_prolog_flag(double_quotes, codes).
