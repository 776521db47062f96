% expect: the load used up its inferences
loop :- loop.
mission.
:- loop.
