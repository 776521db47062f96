% Shared by the bad-rules fixtures: open the link and dive to the tank
% mission's first setpoint (0.6 m), so that what goes wrong next happens
% with the vehicle under water. Not a mission by itself.
dive :-
    ood('start_network', _),
    exec_next_setpt_data(_),
    exec_start_depth_filter(_),
    exec_sleep(1, _),
    exec_submerge(_),
    exec_sleep(8, _).
