% Rules that dive, then block in Prolog's own sleep/1 for a minute between
% two primitive calls: the event loop's thread is inside SWI-Prolog, and a
% signal must still end the run, with the vehicle surfaced.
mission_data('../../missions/tank/setpoints.toml').
:- consult(dive_to_setpoint).

mission :- dive, sleep(60), exec_surface(_).
