% Rules that command the dive without starting the depth filter: the
% vehicle answers `exec submerge` with 0 and says why in an event; the
% run's summary must give that reason.
mission_data('../../missions/tank/setpoints.toml').

mission :- ood('start_network', _), exec_next_setpt_data(_), exec_submerge(_).
