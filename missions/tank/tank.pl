% The tank mission of the paper (§4) as PROLOG rules, in the style of its
% Figure 10: the same four phases as tank.coral, asking the same questions
% in the same order, so `strata compare tank.coral tank.pl` finds the same
% primitive calls in every scenario. Phase 2 is in phase2.pl (Figure 10
% itself can take its place: the test suite does exactly that).
%
% The rules call the vehicle primitives of the catalogue (`strata
% primitives`): exec_<name>(..., X), ask_<name>(X), ood('<name>', X),
% report(Text); X is unified with the vehicle's answer, 1 or 0.
% strata runs mission/0; see docs/prolog.md.

% The mission's state, changed as phases end (Figure 10's asserta/retract).
:- dynamic current_phase/1, complete/1, abort/1.
% Phases are written across files: each file adds its own clauses.
:- multifile execute_phase/1, phase_completed/1, next_phase/1, done/0.
:- discontiguous execute_phase/1, phase_completed/1, next_phase/1.

mission_data('setpoints.toml').

:- consult(phase2).

current_phase(1).

% The phase loop. The cut after each phase keeps Prolog from backtracking
% into a phase that has ended (its `repeat` would run it again).
mission :-
    repeat,
        step,
        mission_over,
    !,
    finish.

step :-
    current_phase(P),
    execute_phase(P), !,
    next_phase(P), !.

mission_over :- current_phase(mission_complete).
mission_over :- current_phase(mission_abort).

% A phase that aborted: say so, then Figure 10's `done` shuts the vehicle
% network down (done/0 for an abort is in phase2.pl, as in the paper).
finish :-
    current_phase(mission_abort),
    report('mission aborted: shutting down the vehicle network'),
    done.
finish :-
    done.

done :-
    current_phase(mission_complete),
    ood('shutdown_network', _).

% Phase 1: open the link to the Execution level; go on only if the vehicle
% reports no system problem.
execute_phase(1) :-
    ood('start_network', X), X = 1,
    phase_completed(1).

phase_completed(1) :-
    ask_system_problem(X), X = 1,
    report('phase 1: system problem at start-up'),
    asserta(abort(1)).
phase_completed(1) :-
    asserta(complete(1)).

next_phase(1) :-
    complete(1),
    retract(current_phase(1)),
    asserta(current_phase(2)).
next_phase(1) :-
    abort(1),
    retract(current_phase(1)),
    asserta(current_phase(mission_abort)).

% Phase 3: submerge to the second setpoint. The depth filter runs already;
% otherwise the same watch as phase 2.
execute_phase(3) :-
    exec_next_setpt_data(X),
    exec_submerge(X), X = 1,
    exec_start_timer(X),
    repeat,
    phase_completed(3).

phase_completed(3) :-
    exec_sleep(1, X),
    ask_depth_reached(X), X = 1,
    asserta(complete(3)).
phase_completed(3) :-
    ask_time_out(X), X = 1,
    surface,
    asserta(abort(3)).
phase_completed(3) :-
    ask_system_problem(X), X = 1,
    surface,
    asserta(abort(3)).

% Emergency: command the surface and ask until it is reached.
surface :-
    exec_surface(X), X = 1,
    repeat,
    ask_surface_reached(Y), Y = 1,
    !.

next_phase(3) :-
    complete(3),
    retract(current_phase(3)),
    asserta(current_phase(4)).
next_phase(3) :-
    abort(3),
    retract(current_phase(3)),
    asserta(current_phase(mission_abort)).

% Phase 4: return to the surface within the last setpoint's time limit.
execute_phase(4) :-
    exec_next_setpt_data(X),
    exec_surface(X), X = 1,
    exec_start_timer(X),
    repeat,
    phase_completed(4).

phase_completed(4) :-
    exec_sleep(1, X),
    ask_surface_reached(X), X = 1,
    asserta(complete(4)).
phase_completed(4) :-
    ask_time_out(X), X = 1,
    report('phase 4: surface not reached in time'),
    asserta(abort(4)).

next_phase(4) :-
    complete(4),
    retract(current_phase(4)),
    asserta(current_phase(mission_complete)).
next_phase(4) :-
    abort(4),
    retract(current_phase(4)),
    asserta(current_phase(mission_abort)).
