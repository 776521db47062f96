% expect: use_foreign_library/1 is not allowed in a mission
mission.
:- use_foreign_library(foreign(marker)).
