% Rules that dive and then call halt/0 with the vehicle under water: an
% abort (exit 1), and strata surfaces the vehicle.
mission_data('../../missions/tank/setpoints.toml').
:- consult(dive_to_setpoint).

mission :- dive, halt.
