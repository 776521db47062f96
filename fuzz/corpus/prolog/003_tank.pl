% The tank mission of the paper (§4) as PROLOG rules, in the style of its
% Figure 10: the same four phases as tank.coral, asking the same questions
% in the same order, so `strata compare tank.coral tank.pl` finds the same
% primitive calls in every scenario. Phase 2 is in phase2.pl (Figure 10
% itself can take its place: the test suite does exactly that); the phase
% loop and phases 1 and 4, shared with the sonar search, in phases.pl.
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
:- consult(phases).

current_phase(1).

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
