% expect: shell/1 is not allowed in a mission
mission.
:- shell('touch marker').
