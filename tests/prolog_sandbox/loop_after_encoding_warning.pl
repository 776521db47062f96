% expect: the load used up its inferences
% Regression (fuzz/prolog_fuzz.cpp): a warning while loading (this comment
% is not UTF-8: Š) lifted the directives' inference budget, and the loop ran for ever.
loop :- loop.
mission.
:- loop.
