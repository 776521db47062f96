% A PROLOG mission that looks for a target with the sonar and slides
% sideways (lines 10 and 11, column 5). Checked for an IMC vehicle (`strata
% check --vehicle imc://HOST:PORT`, or `strata run` with that vehicle),
% which switches the sonar on and off but sends no sweeps and takes no
% sideways speed, both calls are refused at their place when the rules
% load, before the vehicle is reached; exit 65. The sonar's start and stop
% pass. For the Phoenix protocol it checks clean.
mission :-
    ood('start_network', X), X = 1, exec_heading(90, _), exec_start_sonar(_),
    ask_target_detected(T), T = 1,
    exec_set_sway(0.1, _),
    exec_stop_sonar(_).
