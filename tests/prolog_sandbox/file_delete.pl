% expect: delete_file/1 is not allowed in a mission
mission.
:- delete_file(marker).
