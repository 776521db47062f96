% The library phase rows in a mission: the rules twin of rows.coral.
:- use_phase(rows).
:- use_phase(abort_surface).

mission :-
    ood(start_network, _),
    rows(0, 0, 90, 40, 10, 3, 3, 1, complete),
    abort_surface(surfaced),
    ood(shutdown_network, _).
