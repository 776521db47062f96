/*  loiter(+X, +Y, +Radius, +Seconds, -Exit): Strata's library phase
    (docs/library.md), the rules twin of library/coral/loiter.coral: circle
    (X, Y) m at Radius m for Seconds s. Exit: done. A mission loads it with
    `:- use_phase(loiter).`
*/
loiter(X, Y, Radius, Seconds, Exit) :-
    exec_loiter(X, Y, Radius, _),
    exec_sleep(Seconds, _),
    Exit = done.
