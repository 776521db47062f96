/*  abort_surface(-Exit): Strata's library phase (docs/library.md), the
    rules twin of library/coral/abort_surface.coral: the same calls in the
    same order. Stop the propulsion and the guidance, start the surfacing
    manoeuvre, and ask surface_reached once a simulated second until the
    vehicle is up. Exit: surfaced.
    A mission loads it with `:- use_phase(abort_surface).`
*/
abort_surface(Exit) :-
    exec_stop(_),
    exec_surface(_),
    abort_surface_poll,
    Exit = surfaced.

abort_surface_poll :-
    exec_sleep(1, _),
    ask_surface_reached(Up),
    (   Up == 1
    ->  true
    ;   abort_surface_poll
    ).
