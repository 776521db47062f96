% expect: abolish/1 is not allowed in a mission
% Issue 39: refused inside catch/3, the refusal named the wrapper (catch/3)
% rather than the goal the sandbox refused.
mission :- go.
go :- catch(abolish(foo/1), _, true).
