% Rules that dive, then loop for ever without calling a primitive: the
% inference limit stops them and strata run surfaces the vehicle.
mission_data('../../missions/tank/setpoints.toml').
:- consult(dive_to_setpoint).

mission :- dive, spin.

spin :- spin.
