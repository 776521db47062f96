/*  goto(+X, +Y, +Depth, +Speed, -Exit): Strata's library phase
    (docs/library.md), the rules twin of library/coral/goto.coral: the
    same calls in the same order. Down (or up) to Depth m, cruise at Speed
    m/s, steer to the waypoint (X, Y) m, and ask waypoint_reached once a
    simulated second until it is reached. Exit: arrived.
    A mission loads it with `:- use_phase(goto).`
*/
goto(X, Y, Depth, Speed, Exit) :-
    exec_goto_depth(Depth, _),
    exec_set_speed(Speed, _),
    exec_goto_xy(X, Y, _),
    goto_poll,
    Exit = arrived.

goto_poll :-
    exec_sleep(1, _),
    ask_waypoint_reached(Reached),
    (   Reached == 1
    ->  true
    ;   goto_poll
    ).
