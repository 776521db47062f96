% The sonar search (issue 8) as PROLOG rules, in the style of the paper's
% Figure 10: the same four phases as sonar_search.coral, making the same
% primitive calls in the same order, so `strata compare sonar_search.coral
% sonar_search.pl` agrees in every scenario. The phase loop and phases 1, 2
% and 4 are the tank mission's (../tank/phases.pl and ../tank/phase2.pl);
% this file holds phase 3, the search.
%
% The rules call the vehicle primitives of the catalogue (`strata
% primitives`): exec_<name>(..., X), ask_<name>(X), ood('<name>', X),
% report(Text); X is unified with the vehicle's answer, 1 or 0.

:- dynamic current_phase/1, complete/1, abort/1.
:- multifile execute_phase/1, phase_completed/1, next_phase/1, done/0.
:- discontiguous execute_phase/1, phase_completed/1, next_phase/1.

mission_data('setpoints.toml').

:- consult('../tank/phase2').
:- consult('../tank/phases').

current_phase(1).

% Phase 3: the search. Read its setpoint (the time limit), start the timer
% and the sonar, then look at each heading in turn (0, 45, ... 315, and
% round again); after each look, watch for a system problem, the time-out
% and the depth. A target seen completes the phase; a problem or the
% time-out stops the sonar, surfaces and aborts.
execute_phase(3) :-
    exec_next_setpt_data(_),
    exec_start_timer(_),
    exec_start_sonar(_),
    search(0).

% Turn to heading K * 45 degrees, give the sonar a sweep, look.
search(K) :-
    Degrees is K * 45,
    exec_heading(Degrees, _),
    exec_sleep(5, _),
    look(K).

look(K) :-
    ask_heading_reached(H),
    H =:= 1, !,
    ask_target_detected(T),
    seen(T, K).
look(K) :-
    watch(Go),
    still_turning(Go, K).

still_turning(go, K) :-
    exec_sleep(2, _),
    look(K).
still_turning(stop, _).

seen(1, _) :-
    report('search: target detected'),
    exec_stop_sonar(_),
    asserta(complete(3)).
seen(0, K) :-
    watch(Go),
    next_heading(Go, K).

next_heading(go, K) :-
    Next is (K + 1) mod 8,
    search(Next).
next_heading(stop, _).

% The watch: go on, or give up (and say why).
watch(Go) :-
    ask_system_problem(P),
    watch_problem(P, Go).

watch_problem(1, stop) :-
    report('search: system problem'),
    give_up.
watch_problem(0, Go) :-
    ask_time_out(T),
    watch_time(T, Go).

watch_time(1, stop) :-
    report('search: time-out, target not found'),
    give_up.
watch_time(0, go) :-
    ask_depth_reached(D),
    depth_held(D).

depth_held(1).
depth_held(0) :-
    report('search: off the depth setpoint').

give_up :-
    exec_stop_sonar(_),
    exec_surface(_),
    repeat,
    ask_surface_reached(S), S =:= 1,
    !,
    asserta(abort(3)).

next_phase(3) :-
    complete(3),
    retract(current_phase(3)),
    asserta(current_phase(4)).
next_phase(3) :-
    abort(3),
    retract(current_phase(3)),
    asserta(current_phase(mission_abort)).
