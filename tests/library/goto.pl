% The library phase goto in a mission: the rules twin of goto.coral
% (tests/library_test.cpp compares the two call for call).
:- use_phase(goto).
:- use_phase(abort_surface).

mission :-
    ood(start_network, _),
    goto(40, 30, 3, 1, arrived),
    abort_surface(surfaced),
    ood(shutdown_network, _).
