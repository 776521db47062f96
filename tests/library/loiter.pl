% The library phases loiter and station_keep in a mission: the rules twin
% of loiter.coral.
:- use_phase(goto).
:- use_phase(loiter).
:- use_phase(station_keep).
:- use_phase(abort_surface).

mission :-
    ood(start_network, _),
    goto(0, 0, 2, 1, arrived),
    loiter(20, 20, 10, 60, done),
    station_keep(30, done),
    abort_surface(surfaced),
    ood(shutdown_network, _).
