% Rules that dive, then raise an error: the mission fails with the error's
% text and strata run surfaces the vehicle.
mission_data('../../missions/tank/setpoints.toml').
:- consult(dive_to_setpoint).

mission :- dive, Seconds is 1 / 0, exec_sleep(Seconds, _).
