% expect: a directive ran too long while loading
loop :- catch(spin, _, true), loop.
spin :- spin.
mission.
:- loop.
