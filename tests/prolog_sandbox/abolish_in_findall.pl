% expect: abolish/1 is not allowed in a mission
% Issue 39: refused inside findall/3, the refusal named findall/3.
mission :- go.
go :- findall(x, abolish(bar/1), _).
