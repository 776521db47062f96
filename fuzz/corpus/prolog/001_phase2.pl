% Phase 2 of the tank mission: dive away from the surface to the first
% setpoint. Our own rules, written to behave as the paper's Figure 10 (which
% can replace this file unchanged): read the setpoint, start the depth
% filter if it is off, submerge, start the timer; then, once a cycle, ask in
% turn whether the depth is reached, whether time is out, whether there is a
% system problem. Time-out or a problem surfaces the vehicle and aborts.
% Loaded by tank.pl, which declares the predicates shared across files.

% A phase that aborted ends the mission with the vehicle network shut down.
done :-
    current_phase(mission_abort),
    ood('shutdown_network', _).

execute_phase(2) :-
    exec_next_setpt_data(X),
    start_depth_filter,
    exec_submerge(X), X = 1,
    exec_start_timer(X),
    repeat,
    phase_completed(2).

start_depth_filter :-
    ask_depth_filter_off(X), X = 1,
    exec_start_depth_filter(X),
    exec_sleep(1, X).
start_depth_filter.

phase_completed(2) :-
    exec_sleep(1, X),
    ask_depth_reached(X), X = 1,
    asserta(complete(2)).
phase_completed(2) :-
    ask_time_out(X), X = 1,
    exec_surface(X),
    repeat,
    ask_surface_reached(X), X = 1,
    asserta(abort(2)).
phase_completed(2) :-
    ask_system_problem(X), X = 1,
    exec_surface(X),
    repeat,
    ask_surface_reached(X), X = 1,
    asserta(abort(2)).

next_phase(2) :-
    complete(2),
    retract(current_phase(2)),
    asserta(current_phase(3)).
next_phase(2) :-
    abort(2),
    retract(current_phase(2)),
    asserta(current_phase(mission_abort)).
