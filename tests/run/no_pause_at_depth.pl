% pause_at_depth.pl without its pause: the run it must equal.
mission_data('../../missions/tank/setpoints.toml').
:- consult(dive_to_setpoint).

mission :- dive, exec_surface(_).
