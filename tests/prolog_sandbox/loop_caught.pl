% expect: (the load used up its inferences|loading took longer than its time limit)
loop :- catch(spin, _, true), loop.
spin :- spin.
mission.
:- loop.
