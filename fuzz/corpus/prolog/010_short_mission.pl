% Opens and closes the vehicle network, nothing else: `strata compare`
% against tank.coral parts at the second call (exit 1).
mission :-
    ood('start_network', X), X = 1,
    ood('shutdown_network', _).
