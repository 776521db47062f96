% Rules that dive, then block in Prolog's own sleep/1 for longer than the
% vehicle's watchdog (3 s) between two primitive calls. In lockstep the
% simulation waits for them: the pause must change nothing in the run.
mission_data('../../missions/tank/setpoints.toml').
:- consult(dive_to_setpoint).

mission :- dive, sleep(4), exec_surface(_).
