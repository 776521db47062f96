% expect: process_create/3 is not allowed in a mission
mission.
:- process_create(path(touch), [marker], []).
