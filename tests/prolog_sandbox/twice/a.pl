% Loads b.pl twice (consulted, then included): what b.pl says wrong
% is said twice, and counted once (strata check: a.pl: 2 errors).
mission :- p.
:- consult(b).
:- include(b).
