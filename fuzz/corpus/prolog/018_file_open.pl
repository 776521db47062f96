% expect: open/3 is not allowed in a mission
mission.
:- open(marker, write, S), close(S).
