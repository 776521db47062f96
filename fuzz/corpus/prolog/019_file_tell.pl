% expect: tell/1 is not allowed in a mission
mission.
:- tell(marker), told.
