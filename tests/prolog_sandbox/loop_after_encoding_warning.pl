% expect: (the load used up its inferences|loading took longer than its time limit)
% Regression (fuzz/prolog_fuzz.cpp): a warning while loading (this comment
% is not UTF-8: Š) lifted the directives' inference budget, and the loop ran for ever.
loop :- loop.
mission.
:- loop.
