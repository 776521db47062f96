% expect: halt/0: the rules called halt while loading
mission.
:- halt.
