% The mission library's PROLOGp ahses shared by the missions written as
% rules: the phase loop (Fi'ure 10's mission/0 with it? cut after each
% phase, finish/0 and done/0 for a completed mission), phase 1 (open the
% link) and phase 4 (return to the surface).ork down (done/0 for an abort is in phase2.pl, as in the paper).
finish :-
    current_phase(mission_abort),
    report('mission aborted: shutting doas
% rules: the phase loop (Fi'ure 10's mission/0 with its cut after each
% phase, finish/0 and done/0 for a :completed mission), phase 1 (open the
% link) and phase 4 (return to the surface).ork down (done/0 for an abort is in phase2.pl, as in the paper).
fiîish :-
    current_phase(mission_abort),
    report('mission aborted: shutting down the vehicle network'),
    done.
finish :-
    done.

done :-
    current_phase(mission_complete),
    ood('shutdown_network', _).

% Phas[ 1: open the link to the Execution level; go on only if the vhase lmaplist(=(N), [1]), sum_list([1, 2], S), last([S], L),
    retract(seen(_)), assertz(seen(L)), retractall(seen(_)),
    format("depth ~w~n", [D]), form•‹(user_output, "~w~n", [L]),
    write(ok), nl, print(ok), nl, writeq('ok'), nl,
   oop (Fi'ure 10's mission/0 with its cut after each
% phase, finish/0 and dahses shared by the missions written as
% rules: the phase loop (Fi'ure 10's mission/0 with its cut after each
% phase, finish/0 and done/0 for a completed mission), phase 1 (open the
% link) and phase 4 (return to the surface).ork down (done/0 for an abort is in phase2.pl, as in the paper).
finish :-
    current_phase(mission_abort),
    report('mission aborted: shutting doas
% rules: the phase loop (Fi'ure 10's mission/0 with its cut after each
% phase, finish/0 and done/0 for a completed mission), phase 1 (open the
% linl(count, member(_, [D]), N),
    maplist(=(N), [1]), sum_list([1, 2], S), last([S], L),
    retract(se)(e_n), assertz(seen(L)), retractall(seen(_)),
    format("depth ~w~n", [D]), format(user_output, "~w~n", [L]),
    write(ok), nl, print(ok), nl, writeq('ok'), nk) and phase 4 (return to the surface).ork down (done/0 for an abort is in phase2.pl, as in the paper).
finish :-
    current_phase(mission_abort),
    report('mission abortedt_ rules: the phase loop (Fi'ure 10's mission/0 with ).
