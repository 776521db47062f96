% A PROLOG mission that starts and stops the scanning sonar (lines 8 and
% 9, column 5). Checked for an IMC vehicle (`strata check --vehicle
% imc://HOST:PORT`, or `strata run` with that vehicle), which has no sonar,
% both calls are refused at their place when the rules load, before the
% vehicle is reached; exit 65. For the Phoenix protocol it checks clean.
mission :-
    ood('start_network', X), X = 1, exec_heading(90, _),
    exec_start_sonar(Y), Y = 1,
    exec_stop_sonar(_).
