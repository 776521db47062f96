/*  rows(+X, +Y, +Heading, +Length, +Spacing, +Count, +Depth, +Speed, -Exit):
    Strata's library phase (docs/library.md), the rules twin of
    library/coral/rows.coral: the same calls in the same order. A lawnmower
    over a rectangle: down (or up) to Depth m, cruise at Speed m/s, record
    the pattern (start_rows), then per row next_row, waypoint_reached asked
    once a simulated second until the row's end, then rows_done.
    Exit: complete. A mission loads it with `:- use_phase(rows).`
*/
rows(X, Y, Heading, Length, Spacing, Count, Depth, Speed, Exit) :-
    exec_goto_depth(Depth, _),
    exec_set_speed(Speed, _),
    exec_start_rows(X, Y, Heading, Length, Spacing, Count, _),
    rows_next,
    Exit = complete.

rows_next :-
    exec_next_row(_),
    rows_poll,
    ask_rows_done(Done),
    (   Done == 1
    ->  true
    ;   rows_next
    ).

rows_poll :-
    exec_sleep(1, _),
    ask_waypoint_reached(Reached),
    (   Reached == 1
    ->  true
    ;   rows_poll
    ).
