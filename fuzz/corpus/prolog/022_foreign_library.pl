% expect: load_foreign_library/1 is not allowed in a mission
mission.
:- load_foreign_library(foreign(libc)).
