% expect: set_prolog_flag/2 is not allowed in a mission
mission :- set_prolog_flag(unknown, fail).
