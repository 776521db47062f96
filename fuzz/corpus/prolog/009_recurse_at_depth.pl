% Rules that dive, then recurse without end: the stack limit (or the
% inference limit) stops them and strata run surfaces the vehicle.
mission_data('../../missions/tank/setpoints.toml').
:- consult(dive_to_setpoint).

mission :- dive, deeper(0).

deeper(N) :- M is N + 1, deeper(M), true.
