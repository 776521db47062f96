% expect: (the load used up its inferences|loading took longer than its time limit)
loop :- loop.
mission.
:- loop.
