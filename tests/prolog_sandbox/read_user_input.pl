% expect: read_term/3 is not allowed in a mission
mission.
:- read_term(user_input, X, []), write(X).
