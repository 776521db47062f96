% The libraries a mission may load (docs/prolog.md, section 7), and the
% console output and database predicates the sandbox allows.
:- use_module(library(lists)).
:- use_module(library(apply)).
:- use_module(library(aggregate)).
:- use_module(library(assoc)).
:- ensure_loaded(library(lists)).
:- dynamic seen/1.
:- assertz(seen(0)).

mission :-
    list_to_assoc([depth-1], A), get_assoc(depth, A, D),
    aggregate_all(count, member(_, [D]), N),
    maplist(=(N), [1]), sum_list([1, 2], S), last([S], L),
    retract(seen(_)), assertz(seen(L)), retractall(seen(_)),
    format("depth ~w~n", [D]), format(user_output, "~w~n", [L]),
    write(ok), nl, print(ok), nl, writeq('ok'), nl,
    exec_sleep(1, _).
