% expect: the load used up its inferences
loop :- catch(spin, _, true), loop.
spin :- spin.
mission.
:- loop.
