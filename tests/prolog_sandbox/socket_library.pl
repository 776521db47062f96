% expect: library[(]socket[)] is not allowed in a mission
mission.
:- use_module(library(socket)).
