% expect: a directive ran too long while loading
loop :- loop.
mission.
:- loop.
