/*  plunit tests for the PROLOG Strategic level's driver (driver.pl).

    Run from any folder:

        swipl --no-packs -q -g "(run_tests -> halt(0) ; halt(1))" -t halt src/prolog/driver_test.pl

    swipl alone has no host, so this file defines stand-ins for the three
    predicates the C++ host normally provides in module strata_driver: they
    record what the rules did as event/1 facts and answer primitive calls
    from a scripted queue (1 once the queue is empty). Rule files are
    written to temporary files at test time.
*/
:- module(strata_driver_test, []).
:- use_module(library(plunit)).
:- use_module(library(lists)).
:- use_module(library(apply)).

:- prolog_load_context(directory, Dir),
   directory_file_path(Dir, 'driver.pl', Driver),
   use_module(Driver).

                 /*******************************
                 *      THE HOST'S STAND-INS    *
                 *******************************/

:- dynamic event/1,              % call(Name, Args), report(Name, Args), phase(Event, Phase)
           answer_queue/1.       % the answers still to give, in order

strata_driver:'$strata_call'(Name, Args, Answer) :-
    strata_driver_test:host_call(Name, Args, Answer).
strata_driver:'$strata_report'(Name, Args) :-
    strata_driver_test:host_event(report(Name, Args)).
strata_driver:'$strata_phase'(Event, Phase) :-
    strata_driver_test:host_event(phase(Event, Phase)).

host_call(Name, Args, Answer) :-
    host_event(call(Name, Args)),
    (   retract(answer_queue([A|As]))
    ->  assertz(answer_queue(As)),
        Answer = A
    ;   Answer = 1
    ).

host_event(E) :-
    assertz(event(E)).

%   script(+Answers): forget what happened so far; the next primitive calls
%   are answered with Answers, in order.
script(Answers) :-
    retractall(event(_)),
    retractall(answer_queue(_)),
    assertz(answer_queue(Answers)).

events(Events) :-
    findall(E, event(E), Events).

                 /*******************************
                 *           HELPERS            *
                 *******************************/

primitives([ primitive(sleep, exec, 1, 1),
             primitive(submerge, exec, 0, 0),
             primitive(depth_reached, ask, 0, 0),
             primitive(shutdown_network, ood, 0, 0),
             primitive(report, report, 1, 1)
           ]).

open_test_mission(M) :-
    primitives(Ps),
    open_mission(M, Ps),
    script([]).

%   rules_file(+Lines, -File): writes Lines (strings), one a line, to a
%   fresh temporary .pl file. Line N of the file is the Nth element.
rules_file(Lines, File) :-
    tmp_file_stream(File, S, [extension(pl), encoding(utf8)]),
    forall(member(L, Lines), format(S, "~w~n", [L])),
    close(S).

%   mission_from(+Lines, -Module, -File): a mission module with Lines loaded.
mission_from(Lines, M, File) :-
    rules_file(Lines, File),
    open_test_mission(M),
    load_mission(M, File).

done_with(M, File) :-
    strata_driver:unlimited,
    close_mission(M),
    catch(delete_file(File), _, true).

load_messages(Messages) :-
    findall(m(K, F, L, C, T), strata_driver:load_message(K, F, L, C, T), Messages).

contains(Text, Part) :-
    sub_string(Text, _, _, _, Part),
    !.

% 100000 inferences of work, to see whether an inference limit is armed.
busy :-
    (   between(1, 100000, _), fail
    ;   true
    ).

                 /*******************************
                 *        open_mission/2        *
                 *******************************/

:- begin_tests(open_mission).

test(defines_the_primitives, [setup(open_test_mission(M)), cleanup(close_mission(M))]) :-
    assertion(current_predicate(M:exec_sleep/2)),
    assertion(current_predicate(M:exec_submerge/1)),
    assertion(current_predicate(M:ask_depth_reached/1)),
    assertion(current_predicate(M:ood/2)),
    assertion(current_predicate(M:report/1)).

test(defines_only_the_arities_in_the_catalogue,
     [setup(open_test_mission(M)), cleanup(close_mission(M))]) :-
    assertion(\+ current_predicate(M:exec_sleep/1)),
    assertion(\+ current_predicate(M:exec_sleep/3)),
    assertion(\+ current_predicate(M:exec_submerge/2)),
    assertion(\+ current_predicate(M:ask_submerge/1)),
    assertion(\+ current_predicate(M:exec_shutdown_network/1)),
    assertion(\+ current_predicate(M:exec_report/2)),
    assertion(\+ current_predicate(M:report/0)),
    assertion(\+ current_predicate(M:ood/3)).

test(exec_with_an_argument, [setup(open_test_mission(M)), cleanup(close_mission(M)),
                             true(X-Events == 1-[call(sleep, [5])])]) :-
    script([1]),
    M:exec_sleep(5, X),
    events(Events).

test(exec_without_arguments, [setup(open_test_mission(M)), cleanup(close_mission(M)),
                              true(X-Events == 0-[call(submerge, [])])]) :-
    script([0]),
    M:exec_submerge(X),
    events(Events).

test(ask, [setup(open_test_mission(M)), cleanup(close_mission(M)),
           true(X-Events == 0-[call(depth_reached, [])])]) :-
    script([0]),
    M:ask_depth_reached(X),
    events(Events).

test(ood, [setup(open_test_mission(M)), cleanup(close_mission(M)),
           true(X-Events == 1-[call(shutdown_network, [])])]) :-
    script([1]),
    M:ood('shutdown_network', X),
    events(Events).

test(report_is_sent_not_called, [setup(open_test_mission(M)), cleanup(close_mission(M)),
                                 true(Events == [report(report, ['all done'])])]) :-
    script([]),
    M:report('all done'),
    events(Events).

test(answers_in_order, [setup(open_test_mission(M)), cleanup(close_mission(M)),
                        true(Xs-Events == [1, 0, 1]-[call(sleep, [1]), call(sleep, [2]), call(sleep, [3])])]) :-
    script([1, 0, 1]),
    findall(X, ( member(S, [1, 2, 3]), M:exec_sleep(S, X) ), Xs),
    events(Events).

test(bound_answer_that_differs_fails_but_the_call_is_made,
     [setup(open_test_mission(M)), cleanup(close_mission(M)),
      true(Events == [call(submerge, [])])]) :-
    script([0]),
    \+ M:exec_submerge(1),
    events(Events).

test(bound_answer_that_matches_succeeds,
     [setup(open_test_mission(M)), cleanup(close_mission(M)),
      true(Events == [call(depth_reached, [])])]) :-
    script([1]),
    M:ask_depth_reached(1),
    events(Events).

test(bound_answer_is_unified_after_the_call,
     [setup(open_test_mission(M)), cleanup(close_mission(M)),
      true(Events == [call(sleep, [7])])]) :-
    % X is 1 but the vehicle answers 0: the call is still made, then fails.
    script([0]),
    X = 1,
    \+ M:exec_sleep(7, X),
    events(Events).

test(ood_with_an_unknown_name, [setup(open_test_mission(M)), cleanup(close_mission(M)),
                                error(existence_error(ood_primitive, warp_drive/0))]) :-
    M:ood(warp_drive, _).

test(ood_with_an_exec_name, [setup(open_test_mission(M)), cleanup(close_mission(M)),
                             error(existence_error(ood_primitive, submerge/0))]) :-
    M:ood(submerge, _).

test(ood_with_an_unknown_name_calls_nothing,
     [setup(open_test_mission(M)), cleanup(close_mission(M)), true(Events == [])]) :-
    script([]),
    catch(M:ood(warp_drive, _), error(existence_error(_, _), _), true),
    events(Events).

test(two_missions_get_two_modules,
     [setup(( open_test_mission(M1), open_test_mission(M2) )),
      cleanup(( close_mission(M1), close_mission(M2) ))]) :-
    assertion(M1 \== M2),
    M1:assertz(only_here),
    assertion(\+ current_predicate(M2:only_here/0)),
    assertion(current_predicate(M2:exec_sleep/2)).

test(no_primitives, [setup(open_mission(M, [])), cleanup(close_mission(M))]) :-
    assertion(\+ current_predicate(M:ood/2)),
    assertion(\+ current_predicate(M:report/1)).

:- end_tests(open_mission).

                 /*******************************
                 *            halt/0,1          *
                 *******************************/

:- begin_tests(halt).

test(halt_0_throws, [setup(open_test_mission(M)), cleanup(close_mission(M)),
                     true(E == strata_halt)]) :-
    catch(M:halt, E, true).

test(halt_1_throws, [setup(open_test_mission(M)), cleanup(close_mission(M)),
                     true(E == strata_halt(3))]) :-
    catch(M:halt(3), E, true).

test(halt_in_the_rules,
     [setup(mission_from(["mission :- exec_submerge(_), halt."], M, F)),
      cleanup(done_with(M, F)),
      true(E-Events == strata_halt-[call(submerge, [])])]) :-
    script([]),
    catch(run_mission(M, 100000), E, true),
    strata_driver:unlimited,
    events(Events).

test(halt_with_a_code_in_the_rules,
     [setup(mission_from(["mission :- exec_submerge(_), stop.",
                          "stop :- halt(2)."], M, F)),
      cleanup(done_with(M, F)),
      true(E == strata_halt(2))]) :-
    catch(run_mission(M, 100000), E, true),
    strata_driver:unlimited.

test(halt_in_the_rules_checks_clean,
     [setup(mission_from(["mission :- halt.", "stop :- halt(1)."], M, F)),
      cleanup(done_with(M, F)),
      true(Problems == [])]) :-
    check_mission(M, Problems).

:- end_tests(halt).

                 /*******************************
                 *        load_mission/2        *
                 *******************************/

:- begin_tests(load_mission).

test(syntax_error_has_its_line,
     [setup(mission_from(["mission :- true.",
                          "",
                          "p(X :- q.",
                          "ok."], M, F)),
      cleanup(done_with(M, F))]) :-
    load_messages(Messages),
    assertion(memberchk(m(error, F, 3, _, _), Messages)),
    memberchk(m(error, F, 3, Column, Text), Messages),
    assertion(integer(Column)),
    assertion(Column > 0),
    assertion(string(Text)),
    assertion(Text \== ""),
    % the clauses around it still load
    assertion(current_predicate(M:mission/0)),
    assertion(current_predicate(M:ok/0)).

% The place is given apart (file, line, column): the text does not repeat it
% (the host prints "file:line:col: error: Text").
test(syntax_error_text_without_the_place,
     [setup(mission_from(["mission :- true.", "p(X :- q."], M, F)),
      cleanup(done_with(M, F))]) :-
    load_messages(Messages),
    memberchk(m(error, F, 2, _, Text), Messages),
    assertion(contains(Text, "Syntax error")),
    assertion(\+ contains(Text, F)).

test(syntax_error_on_the_first_line,
     [setup(mission_from(["mission :- exec_submerge(X.", "ok."], M, F)),
      cleanup(done_with(M, F))]) :-
    load_messages(Messages),
    assertion(memberchk(m(error, F, 1, _, _), Messages)).

test(singleton_is_a_warning,
     [setup(mission_from(["mission :- true.",
                          "p(X) :- true."], M, F)),
      cleanup(done_with(M, F))]) :-
    load_messages(Messages),
    assertion(Messages = [m(warning, F, 2, _, _)]),
    Messages = [m(_, _, _, _, Text)],
    assertion(contains(Text, "X")).

test(redefining_a_primitive_is_an_error,
     [setup(mission_from(["mission :- exec_submerge(_).",
                          "exec_submerge(1)."], M, F)),
      cleanup(done_with(M, F))]) :-
    load_messages(Messages),
    assertion(memberchk(m(error, F, 2, _, _), Messages)),
    memberchk(m(error, F, 2, _, Text), Messages),
    assertion(contains(Text, "exec_submerge/1 is Strata's")).

test(redefining_halt_is_an_error,
     [setup(mission_from(["halt :- true.", "mission :- halt."], M, F)),
      cleanup(done_with(M, F))]) :-
    load_messages(Messages),
    assertion(memberchk(m(error, F, 1, _, _), Messages)).

test(clean_file_has_no_messages,
     [setup(mission_from([":- dynamic seen/1.",
                          "mission :- exec_submerge(X), X == 1, assertz(seen(X))."], M, F)),
      cleanup(done_with(M, F)),
      true(Messages == [])]) :-
    load_messages(Messages).

test(messages_of_an_earlier_load_are_forgotten,
     [setup(( mission_from(["p(X :- q."], M1, F1),
              mission_from(["mission."], M2, F2) )),
      cleanup(( done_with(M1, F1), done_with(M2, F2) )),
      true(Messages == [])]) :-
    load_messages(Messages).

test(missing_file_is_an_error,
     [setup(( open_test_mission(M),
              tmp_file(strata_missing, F0),
              atom_concat(F0, '.pl', F) )),
      cleanup(close_mission(M))]) :-
    load_mission(M, F),
    load_messages(Messages),
    assertion(memberchk(m(error, _, _, _, _), Messages)).

test(clauses_go_into_the_mission_module,
     [setup(mission_from(["mission :- true.", "helper(1)."], M, F)),
      cleanup(done_with(M, F))]) :-
    assertion(current_predicate(M:helper/1)),
    assertion(\+ current_predicate(user:helper/1)),
    assertion(\+ current_predicate(strata_driver:helper/1)).

:- end_tests(load_mission).

                 /*******************************
                 *        check_mission/2       *
                 *******************************/

:- begin_tests(check_mission).

test(unknown_exec_primitive,
     [setup(mission_from(["mission :- start.",
                          "start :- exec_warp_drive(X), X = 1."], M, F)),
      cleanup(done_with(M, F))]) :-
    check_mission(M, Problems),
    assertion(Problems = [problem(F, 2, _)]),
    Problems = [problem(_, _, Text)],
    assertion(contains(Text, "exec_warp_drive/1")),
    assertion(contains(Text, "`warp_drive` is not an exec primitive")).

test(unknown_ask_primitive,
     [setup(mission_from(["mission :- true.",
                          "",
                          "go :- ask_nothing(_)."], M, F)),
      cleanup(done_with(M, F))]) :-
    check_mission(M, Problems),
    assertion(Problems = [problem(F, 3, _)]),
    Problems = [problem(_, _, Text)],
    assertion(contains(Text, "`nothing` is not an ask primitive")).

test(wrong_arity_of_a_known_primitive,
     [setup(mission_from(["mission :- true.",
                          "go :- exec_sleep(X), X == 1."], M, F)),
      cleanup(done_with(M, F))]) :-
    check_mission(M, Problems),
    assertion(Problems = [problem(F, 2, _)]),
    Problems = [problem(_, _, Text)],
    assertion(contains(Text, "exec_sleep/1")),        % the arity in use
    assertion(contains(Text, "use exec_sleep/2")).    % the arity to use

test(too_many_arguments_of_a_known_primitive,
     [setup(mission_from(["mission :- exec_submerge(1, X), X == 1."], M, F)),
      cleanup(done_with(M, F))]) :-
    check_mission(M, Problems),
    assertion(Problems = [problem(F, 1, _)]),
    Problems = [problem(_, _, Text)],
    assertion(contains(Text, "exec_submerge/2")),
    assertion(contains(Text, "use exec_submerge/1")).

test(plain_undefined_predicate,
     [setup(mission_from(["mission :- go.",
                          "go :- true.",
                          "go :- frobnicate(1, 2)."], M, F)),
      cleanup(done_with(M, F))]) :-
    check_mission(M, Problems),
    assertion(Problems = [problem(F, 3, _)]),
    Problems = [problem(_, _, Text)],
    assertion(contains(Text, "frobnicate/2 is called but not defined")).

test(missing_mission,
     [setup(mission_from(["go :- exec_submerge(_)."], M, F)),
      cleanup(done_with(M, F))]) :-
    check_mission(M, Problems),
    assertion(Problems = [problem('', 0, _)]),
    Problems = [problem(_, _, Text)],
    assertion(contains(Text, "no mission/0")).

test(missing_mission_and_an_undefined_call,
     [setup(mission_from(["go :- exec_warp_drive(_)."], M, F)),
      cleanup(done_with(M, F))]) :-
    check_mission(M, Problems),
    assertion(Problems = [problem('', 0, _), problem(F, 1, _)]).

test(problems_are_sorted_by_line,
     [setup(mission_from(["mission :- a, b.",
                          "b :- exec_warp_drive(_).",
                          "a :- undefined_thing."], M, F)),
      cleanup(done_with(M, F))]) :-
    check_mission(M, Problems),
    assertion(Problems = [problem(F, 2, _), problem(F, 3, _)]).

% A call on a later line of its clause is reported at the call's own line
% (the clause's first line would do for a one-line clause).
test(problem_at_the_line_of_the_call,
     [setup(mission_from(["% a comment with non-ASCII text: Ünïcödé — before the rules",
                          "mission :-",
                          "    true,",
                          "    exec_warp_drive(_),",
                          "    findall(X, ( member(X, [1]),",
                          "                 ask_nowhere(X) ), _).",
                          "go :- frobnicate(1),",
                          "      frobnicate(2)."], M, F)),
      cleanup(done_with(M, F))]) :-
    check_mission(M, Problems),
    assertion(Problems = [problem(F, 4, _), problem(F, 6, _), problem(F, 7, _), problem(F, 8, _)]),
    Problems = [problem(_, _, T4), problem(_, _, T6), problem(_, _, T7), problem(_, _, T8)],
    assertion(contains(T4, "exec_warp_drive/1")),
    assertion(contains(T6, "ask_nowhere/1")),
    assertion(contains(T7, "frobnicate/1")),
    assertion(contains(T8, "frobnicate/1")).

test(clean_file,
     [setup(mission_from([":- dynamic seen/1, current_phase/1.",
                          "mission :- exec_sleep(1, X), X == 1, ask_depth_reached(_),",
                          "           ood('shutdown_network', _), report(done),",
                          "           member(A, [1, 2]), format(atom(_), '~w', [A]),",
                          "           ( seen(_) -> true ; assertz(seen(1)) ),",
                          "           ( current_phase(mission_abort) -> halt ; halt(0) ).",
                          "mission_data('data.csv')."], M, F)),
      cleanup(done_with(M, F)),
      true(Problems == [])]) :-
    check_mission(M, Problems).

test(problems_of_an_earlier_check_are_forgotten,
     [setup(( mission_from(["mission :- frobnicate."], M1, F1),
              mission_from(["mission."], M2, F2) )),
      cleanup(( done_with(M1, F1), done_with(M2, F2) )),
      true(Problems == [])]) :-
    check_mission(M1, [_]),
    check_mission(M2, Problems).

:- end_tests(check_mission).

                 /*******************************
                 *         run_mission/2        *
                 *******************************/

:- begin_tests(run_mission).

test(runs_mission_and_unifies_answers,
     [setup(mission_from([":- dynamic seen/1.",
                          "mission :- exec_sleep(2, X), X == 1, ask_depth_reached(Y), Y == 0,",
                          "           ood('shutdown_network', Z), integer(Z), report('all done'),",
                          "           assertz(seen(ok))."], M, F)),
      cleanup(done_with(M, F)),
      true(Events == [ call(sleep, [2]),
                       call(depth_reached, []),
                       call(shutdown_network, []),
                       report(report, ['all done'])
                     ])]) :-
    script([1, 0, 1]),
    run_mission(M, 100000),
    events(Events),
    assertion(M:seen(ok)).

test(bound_answer_checked_after_the_call,
     [setup(mission_from(["mission :- exec_sleep(1, X), ( exec_submerge(X) -> report(ok) ; report(refused) )."],
                         M, F)),
      cleanup(done_with(M, F)),
      true(Events == [call(sleep, [1]), call(submerge, []), report(report, [refused])])]) :-
    script([1, 0]),
    run_mission(M, 100000),
    events(Events).

test(failing_mission_fails,
     [setup(mission_from(["mission :- exec_submerge(X), X == 1."], M, F)),
      cleanup(done_with(M, F)), fail]) :-
    script([0]),
    run_mission(M, 100000).

test(mission_runs_once,
     [setup(mission_from(["mission :- exec_sleep(1, _).",
                          "mission :- exec_sleep(2, _)."], M, F)),
      cleanup(done_with(M, F)),
      true(Events == [call(sleep, [1])])]) :-
    script([]),
    findall(x, run_mission(M, 100000), Xs),
    assertion(Xs == [x]),
    events(Events).

test(phases_are_reported_with_their_exit,
     [setup(mission_from([":- dynamic current_phase/1, complete/1, abort/1.",
                          "current_phase(1).",
                          "mission :- repeat, step, current_phase(mission_abort), !.",
                          "step :- current_phase(P), ( execute_phase(P) -> true ; true ), next_phase(P), !.",
                          "execute_phase(1) :- exec_submerge(_), asserta(complete(1)).",
                          "execute_phase(2) :- ask_depth_reached(X), X = 1, asserta(abort(2)).",
                          "execute_phase(3) :- exec_sleep(3, _).",
                          "execute_phase(4) :- ask_depth_reached(X), X == 1.",
                          "next_phase(1) :- retract(current_phase(1)), asserta(current_phase(2)).",
                          "next_phase(2) :- retract(current_phase(2)), asserta(current_phase(3)).",
                          "next_phase(3) :- retract(current_phase(3)), asserta(current_phase(4)).",
                          "next_phase(4) :- retract(current_phase(4)), asserta(current_phase(mission_abort))."
                         ], M, F)),
      cleanup(done_with(M, F)),
      true(Events == [ phase(start, 1), call(submerge, []), phase(end(complete), 1),
                       phase(start, 2), call(depth_reached, []), phase(end(abort), 2),
                       phase(start, 3), call(sleep, [3]), phase(end(done), 3),
                       phase(start, 4), call(depth_reached, []), phase(end(failed), 4)
                     ])]) :-
    script([1, 1, 1, 0]),
    run_mission(M, 100000),
    events(Events),
    mission_outcome(M, Outcome),
    assertion(Outcome == aborted).

test(phase_without_primitives,
     [setup(mission_from([":- dynamic complete/1.",
                          "mission :- execute_phase(a), \\+ execute_phase(b).",
                          "execute_phase(a) :- assertz(complete(a)).",
                          "execute_phase(b) :- fail."], M, F)),
      cleanup(done_with(M, F)),
      true(Events == [ phase(start, a), phase(end(complete), a),
                       phase(start, b), phase(end(failed), b) ])]) :-
    script([]),
    run_mission(M, 100000),
    events(Events).

test(run_twice_reports_phases_once,
     [setup(mission_from(["mission :- execute_phase(p).",
                          "execute_phase(p)."], M, F)),
      cleanup(done_with(M, F)),
      true(Events == [phase(start, p), phase(end(done), p)])]) :-
    run_mission(M, 100000),
    script([]),
    run_mission(M, 100000),
    events(Events).

test(without_execute_phase_no_phase_events,
     [setup(mission_from(["mission :- exec_submerge(_)."], M, F)),
      cleanup(done_with(M, F)),
      true(Events == [call(submerge, [])])]) :-
    script([]),
    run_mission(M, 100000),
    events(Events).

test(loop_without_primitives_hits_the_limit,
     [setup(mission_from(["mission :- spin.",
                          "spin :- repeat, fail."], M, F)),
      cleanup(done_with(M, F)),
      true(E == inference_limit_exceeded)]) :-
    catch(run_mission(M, 10000), E, true),
    strata_driver:unlimited.

test(loop_after_a_primitive_hits_the_limit,
     [setup(mission_from(["mission :- exec_submerge(_), spin.",
                          "spin :- repeat, fail."], M, F)),
      cleanup(done_with(M, F)),
      true(E-Events == inference_limit_exceeded-[call(submerge, [])])]) :-
    script([]),
    catch(run_mission(M, 10000), E, true),
    strata_driver:unlimited,
    events(Events).

% 50 gaps of about 1000 inferences: 50000 in all, over the limit of 5000,
% but under it between two calls.
test(the_limit_counts_between_calls,
     [setup(mission_from(["mission :- between(1, 50, _), numlist(1, 300, L), sum_list(L, _),",
                          "           exec_submerge(_), fail.",
                          "mission."], M, F)),
      cleanup(done_with(M, F))]) :-
    script([]),
    run_mission(M, 5000),
    events(Events),
    length(Events, N),
    assertion(N == 50).

% The same work without the calls does exceed the limit: the test above is
% not passing for want of work.
test(the_same_work_without_calls_exceeds_the_limit,
     [setup(mission_from(["mission :- between(1, 50, _), numlist(1, 300, L), sum_list(L, _),",
                          "           fail.",
                          "mission."], M, F)),
      cleanup(done_with(M, F)),
      true(E == inference_limit_exceeded)]) :-
    catch(run_mission(M, 5000), E, true),
    strata_driver:unlimited.

test(no_limit_after_a_run_that_succeeded,
     [setup(mission_from(["mission :- exec_submerge(_)."], M, F)),
      cleanup(done_with(M, F)),
      true(E == none)]) :-
    run_mission(M, 10000),
    catch(( busy, E = none ), E, true).

% A run that ends in an exception (here halt) leaves the limit armed; the
% host lifts it with unlimited/0.
test(limit_armed_after_a_halt,
     [setup(mission_from(["mission :- exec_submerge(_), halt."], M, F)),
      cleanup(done_with(M, F)),
      true(E == inference_limit_exceeded)]) :-
    catch(run_mission(M, 10000), strata_halt, true),
    catch(( busy, E = none ), E, true),
    strata_driver:unlimited.

test(unlimited_lifts_the_limit,
     [setup(mission_from(["mission :- exec_submerge(_), halt."], M, F)),
      cleanup(done_with(M, F)),
      true(E == none)]) :-
    catch(run_mission(M, 10000), strata_halt, true),
    unlimited,
    catch(( busy, E = none ), E, true).

:- end_tests(run_mission).

                 /*******************************
                 *  mission_outcome/2, mission_data/2
                 *******************************/

:- begin_tests(mission_outcome).

test(aborted,
     [setup(mission_from([":- dynamic current_phase/1.",
                          "current_phase(mission_abort).",
                          "mission."], M, F)),
      cleanup(done_with(M, F)),
      true(O == aborted)]) :-
    mission_outcome(M, O).

test(completed_in_another_phase,
     [setup(mission_from([":- dynamic current_phase/1.",
                          "current_phase(3).",
                          "mission."], M, F)),
      cleanup(done_with(M, F)),
      true(O == completed)]) :-
    mission_outcome(M, O).

test(completed_without_current_phase,
     [setup(mission_from(["mission."], M, F)),
      cleanup(done_with(M, F)),
      true(O == completed)]) :-
    mission_outcome(M, O).

test(completed_with_no_phase_facts,
     [setup(mission_from([":- dynamic current_phase/1.", "mission."], M, F)),
      cleanup(done_with(M, F)),
      true(O == completed)]) :-
    mission_outcome(M, O).

test(aborted_after_the_run,
     [setup(mission_from([":- dynamic current_phase/1.",
                          "current_phase(1).",
                          "mission :- exec_submerge(_), retract(current_phase(1)),",
                          "           assertz(current_phase(mission_abort))."], M, F)),
      cleanup(done_with(M, F)),
      true(O1-O2 == completed-aborted)]) :-
    mission_outcome(M, O1),
    run_mission(M, 100000),
    mission_outcome(M, O2).

test(completed_when_current_phase_raises,
     [setup(mission_from(["current_phase(_) :- throw(oops).", "mission."], M, F)),
      cleanup(done_with(M, F)),
      true(O == completed)]) :-
    mission_outcome(M, O).

:- end_tests(mission_outcome).

:- begin_tests(mission_data).

test(atom, [setup(mission_from(["mission.", "mission_data('data/tank.csv')."], M, F)),
            cleanup(done_with(M, F)),
            true(File == "data/tank.csv")]) :-
    mission_data(M, File).

test(string, [setup(mission_from(["mission.", "mission_data(\"tank.csv\")."], M, F)),
              cleanup(done_with(M, F)),
              true(File == "tank.csv")]) :-
    mission_data(M, File).

test(the_first_fact, [setup(mission_from(["mission.", "mission_data(a).", "mission_data(b)."], M, F)),
                      cleanup(done_with(M, F)),
                      true(File == "a")]) :-
    mission_data(M, File).

test(none, [setup(mission_from(["mission."], M, F)),
            cleanup(done_with(M, F)),
            fail]) :-
    mission_data(M, _).

:- end_tests(mission_data).

                 /*******************************
                 *        close_mission/1       *
                 *******************************/

:- begin_tests(close_mission).

rules([ ":- dynamic seen/1.",
        "mission :- exec_submerge(X), assertz(seen(X))."
      ]).

test(the_same_file_loads_again_into_a_fresh_module,
     [setup(( rules(Lines), rules_file(Lines, F) )),
      cleanup(catch(delete_file(F), _, true))]) :-
    open_test_mission(M1),
    load_mission(M1, F),
    script([1]),
    run_mission(M1, 100000),
    assertion(M1:seen(1)),
    close_mission(M1),
    open_test_mission(M2),
    assertion(M1 \== M2),
    load_mission(M2, F),
    load_messages(Messages),
    assertion(Messages == []),
    assertion(current_predicate(M2:mission/0)),
    assertion(\+ M2:seen(_)),               % the first run's facts are gone
    check_mission(M2, Problems),
    assertion(Problems == []),
    script([0]),
    run_mission(M2, 100000),
    findall(X, M2:seen(X), Seen),
    assertion(Seen == [0]),
    close_mission(M2).

test(the_module_is_gone) :-
    rules(Lines),
    mission_from(Lines, M, F),
    close_mission(M),
    catch(delete_file(F), _, true),
    assertion(\+ current_predicate(M:mission/0)),
    assertion(\+ current_predicate(M:exec_submerge/1)).

test(closing_twice_is_harmless) :-
    open_test_mission(M),
    close_mission(M),
    close_mission(M).

:- end_tests(close_mission).
