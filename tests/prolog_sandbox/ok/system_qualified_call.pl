% Regression: a clause with a system:Goal call made SWI-Prolog 9.0.4 abort
% the process (pl-comp.c:4417, assertion source_line_no != -1) when it
% compiled the clause in a sandboxed load; also term_expansion/2 defined by
% the rules (refused, with an error, in tests/prolog_sandbox/).
mission :- system:true, exec_sleep(1, X), system:(X =:= 1), system:format("~w~n", [done]).
