% expect: read/1 is not allowed in a mission
mission.
:- read(X), write(X).
