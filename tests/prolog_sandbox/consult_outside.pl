% expect: consult/1 of .*/etc/passwd.*: a mission loads only .pl files
mission.
:- consult('/etc/passwd').
