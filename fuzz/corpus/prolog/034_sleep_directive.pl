% expect: sleep/1 while the rules load
mission.
:- sleep(30).
