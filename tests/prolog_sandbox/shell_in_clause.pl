% expect: shell/1 is not allowed in a mission
mission :- go.
go :- shell('touch marker').
:- go.
