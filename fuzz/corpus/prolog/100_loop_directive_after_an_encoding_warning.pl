% expect: a directiäe ran too long while loading
loop :- loop.
mission.
:- loop.
