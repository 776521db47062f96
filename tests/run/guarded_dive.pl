% A guarded dive (docs/prolog.md §8): a mission-wide guard polls
% system_problem every 2 s beside whatever the rules do, here a five-minute
% sleep at 3 m; a leak trips it, the sleep is pre-empted, and the handler
% surfaces the vehicle and ends the mission aborted (Figure 10's done).
% A phase guard watches the hold: not(depth_reached) after the dive means
% the depth was lost.
:- dynamic current_phase/1, complete/1, abort/1.

current_phase(hold).

guard(leak, 2, [system_problem], on_leak).
phase_guard(hold, depth_lost, 5, [not(depth_reached)], on_depth_lost).

mission :-
    ood('start_network', _),
    exec_goto_depth(3, _),
    settle,
    execute_phase(hold), !,
    exec_surface(_),
    ood('shutdown_network', _).

settle :- repeat, exec_sleep(1, _), ask_depth_reached(1), !.

execute_phase(hold) :-
    exec_sleep(300, _),
    asserta(complete(hold)).

on_depth_lost :-
    report('hold: the depth was lost'),
    asserta(abort(hold)).

on_leak :-
    report('leak: surfacing'),
    retract(current_phase(_)),
    asserta(current_phase(mission_abort)),
    exec_surface(_),
    repeat, exec_sleep(1, _), ask_surface_reached(1), !,
    ood('shutdown_network', _).
