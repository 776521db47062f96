/*  popup(+WaitS, +Depth, -Exit): Strata's library phase (docs/library.md),
    the rules twin of library/coral/popup.coral: the same calls in the same
    order. Up to the surface (surface_reached asked once a simulated
    second), then at most WaitS s for a GPS fix (set_timer, then each second
    gps_available, and time_out while it is not), then down to Depth m
    again. Exits: fixed, no_fix. A mission loads it with
    `:- use_phase(popup).`
*/
popup(WaitS, Depth, Exit) :-
    exec_surface(_),
    popup_rise,
    exec_set_timer(WaitS, _),
    popup_fix(Got),
    exec_goto_depth(Depth, _),
    Exit = Got.

popup_rise :-
    exec_sleep(1, _),
    ask_surface_reached(Up),
    (   Up == 1
    ->  true
    ;   popup_rise
    ).

popup_fix(Got) :-
    ask_gps_available(Gps),
    (   Gps == 1
    ->  exec_gps_fix(_),
        Got = fixed
    ;   ask_time_out(Late),
        (   Late == 1
        ->  Got = no_fix
        ;   exec_sleep(1, _),
            popup_fix(Got)
        )
    ).
