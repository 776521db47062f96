% A PROLOG mission with a syntax error on line 5: strata run exits 65.
mission :-
    ood('start_network', X),
    X = 1,
    exec_sleep(1 X).
