% A PROLOG mission calling a primitive the catalogue does not have (line 6):
% reported when the rules load, before the vehicle is reached; exit 65.
mission :-
    ood('start_network', X),
    X = 1,
    exec_warp_drive(X).
