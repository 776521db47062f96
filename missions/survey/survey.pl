% The survey mission (survey.coral) as PROLOG rules: the same phases and
% guards, the same calls in the same order, so `strata compare survey.coral
% survey.pl` finds the same trace in every scenario. Phases are terms:
% launch, leg(N), fix(N) (back at the surface between legs) and recover;
% Figure 10's phase loop runs them in turn, and any leg that aborts ends in
% the emergency surfacing and the shutdown of the vehicle network.
%
% Safety runs beside the rules (docs/prolog.md §8): the guard `leak` polls
% system_problem once a second for the whole survey and pre-empts whatever
% runs to bring the vehicle up; each leg has the guard `hazard` for a seabed
% under the floor or a position grown uncertain, which stops the sonar and
% aborts the leg.

:- dynamic current_phase/1, complete/1, abort/1.
:- discontiguous execute_phase/1.

current_phase(launch).

% A problem on board, whatever runs: up to the surface, and the end.
guard(leak, 1, [system_problem], on_leak).
% Under water along a leg: the seabed too close, or the position uncertain.
phase_guard(leg(N), hazard, 1, [altitude_low, position_uncertain], leg_hazard(N)).

% The lawnmower: four legs, 250 m long, 20 m apart (x east, y north, m).
leg_track(1, 0, 0, 250, 0).
leg_track(2, 250, 20, 0, 20).
leg_track(3, 0, 40, 250, 40).
leg_track(4, 250, 60, 0, 60).

% The order of the phases.
after(launch, leg(1)).
after(leg(1), fix(1)).
after(fix(1), leg(2)).
after(leg(2), fix(2)).
after(fix(2), leg(3)).
after(leg(3), fix(3)).
after(fix(3), leg(4)).
after(leg(4), recover).
after(recover, mission_complete).

% The phase loop, with a cut after each phase (docs/prolog.md §1).
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

next_phase(P) :-
    abort(P), !,
    retract(current_phase(P)),
    asserta(current_phase(mission_abort)).
next_phase(P) :-
    after(P, Q),
    retract(current_phase(P)),
    asserta(current_phase(Q)).

% After an abort: up to the surface, then Figure 10's done.
finish :-
    current_phase(mission_abort), !,
    report('survey aborted: surfacing'),
    rise,
    ood('shutdown_network', _).
finish :-
    ood('shutdown_network', _).

% At the surface: network, altitude floor, a fix, two minutes of fixes to
% learn the current, then the dive to 5 m.
execute_phase(launch) :-
    ood('start_network', X), X = 1,
    exec_set_altitude_floor(3, F), F = 1,
    exec_gps_fix(G), G = 1,
    exec_sleep(120, S), S = 1,
    exec_goto_depth(5, D), D = 1,
    asserta(complete(launch)).

% One leg with the sonar on, checked once a second for its end; the sonar
% is stopped when it is reached. The guard `hazard` watches it meanwhile.
execute_phase(leg(N)) :-
    leg_track(N, X0, Y0, X1, Y1),
    exec_track(X0, Y0, X1, Y1, X), X = 1,
    exec_start_sonar(S), S = 1,
    repeat,
    exec_sleep(1, _),
    ask_waypoint_reached(R), R = 1,
    !,
    exec_stop_sonar(T), T = 1,
    asserta(complete(leg(N))).

% The leg's guard tripped: the sonar off, and the leg aborts.
leg_hazard(N) :-
    report('leg: the seabed is under the floor, or the position is uncertain'),
    exec_stop_sonar(S), S = 1,
    asserta(abort(leg(N))).

% The mission's guard tripped: in place of the mission, up to the surface and
% Figure 10's done.
on_leak :-
    report('survey aborted: a problem on board, surfacing'),
    retractall(current_phase(_)),
    asserta(current_phase(mission_abort)),
    rise,
    ood('shutdown_network', _).

% Between legs: up, half a minute of fixes, a fix, down to 5 m again.
execute_phase(fix(N)) :-
    rise,
    exec_sleep(30, S), S = 1,
    exec_gps_fix(G), G = 1,
    exec_goto_depth(5, D), D = 1,
    asserta(complete(fix(N))).

% At the end: up, and a fix.
execute_phase(recover) :-
    rise,
    exec_gps_fix(G), G = 1,
    asserta(complete(recover)).

% Up to the surface: command it, then ask once a second until it is reached.
rise :-
    exec_surface(X), X = 1,
    repeat,
    exec_sleep(1, _),
    ask_surface_reached(Y), Y = 1,
    !.
