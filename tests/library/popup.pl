% The library phase popup in a mission: the rules twin of popup.coral.
% Without a fix the mission ends in abort (Figure 10's mission_abort).
:- use_phase(goto).
:- use_phase(popup).
:- use_phase(abort_surface).
:- dynamic current_phase/1.

mission :-
    ood(start_network, _),
    goto(30, 0, 3, 1, arrived),
    popup(20, 3, Exit),
    abort_surface(surfaced),
    ood(shutdown_network, _),
    (   Exit == no_fix
    ->  assertz(current_phase(mission_abort))
    ;   true
    ).
