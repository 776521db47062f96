% The mission library's PROLOG phases shared by the missions written as
% rules: the phase loop (Figure 10's mission/0 with its cut after each
% phase, finish/0 and done/0 for a completed mission), phase 1 (open the
% link) and phase 4 (return to the surface). A mission file declares the
% state predicates and phases as dynamic, multifile and discontiguous, sets
% current_phase(1), consults this file and phase2.pl, and writes its own
% phase 3: tank.pl (submerge to depth) and ../sonar_search/sonar_search.pl
% (the sonar search).

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
