/*  station_keep(+Seconds, -Exit): Strata's library phase
    (docs/library.md), the rules twin of library/coral/station_keep.coral:
    hold the position of now for Seconds s. Exit: done. A mission loads it
    with `:- use_phase(station_keep).`
*/
station_keep(Seconds, Exit) :-
    exec_hold_position(_),
    exec_sleep(Seconds, _),
    Exit = done.
