/*  plunit tests for the PROLOG Strategic level's driver (driver.pl):
    opening a mission (the primitives defined from the catalogue), halt,
    loading a mission's rules (load messages) and checking them.
    driver_test_run.pl tests running, the outcome, mission data and
    closing a mission.

    Run from any folder:

        swipl --no-packs -q -g "(run_tests -> halt(0) ; halt(1))" -t halt src/strategic/prolog/driver_test_load.pl

    or load it with `swipl src/strategic/prolog/driver_test_load.pl` and ask
    `?- run_tests.`

    swipl alone has no host: driver_test_support.pl defines stand-ins for
    the three predicates the C++ host normally provides in module
    strata_driver (they record what the rules did as events and answer
    primitive calls from a scripted queue), and the helpers shared by the
    tests. Rule files are written to temporary files at test time.
*/
:- module(strata_driver_test_load, []).
:- use_module(library(plunit)).
:- use_module(library(lists)).
:- use_module(library(apply)).

:- prolog_load_context(directory, Dir),
   directory_file_path(Dir, 'driver.pl', Driver),
   use_module(Driver),
   directory_file_path(Dir, 'driver_test_support.pl', Support),
   use_module(Support).

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

test(report_of_a_number_or_term_is_text, [setup(open_test_mission(M)), cleanup(close_mission(M)),
                                          true(Events == [report(report, ["42"]), report(report, ["depth(1.5)"])])]) :-
    M:report(42),
    M:report(depth(1.5)),
    events(Events).

test(ood_with_an_unbound_name, [setup(open_test_mission(M)), cleanup(close_mission(M)),
                                error(instantiation_error)]) :-
    M:ood(_, _).

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

test(halt_needs_an_integer, [setup(open_test_mission(M)), cleanup(close_mission(M)),
                             error(type_error(integer, foo))]) :-
    M:halt(foo).

test(system_halt_throws_while_a_mission_is_active,
     [setup(open_test_mission(M)), cleanup(( retractall(strata_driver:active(_)),
                                             close_mission(M) )),
      true(E1-E0-Requested == strata_halt(3)-strata_halt-false)]) :-
    asserta(strata_driver:active(M)),
    catch(system:halt(3), E1, true),
    catch(system:halt, E0, true),
    ( strata_driver:halt_requested(_) -> Requested = true ; Requested = false ).

test(a_halt_that_reaches_swi_is_cancelled_while_a_mission_is_active,
     [setup(open_test_mission(M)), cleanup(( retractall(strata_driver:active(_)),
                                             retractall(strata_driver:halt_requested(_)),
                                             close_mission(M) )),
      true(Requested-E == true-strata_halt)]) :-
    asserta(strata_driver:active(M)),
    catch(strata_driver:cancel_mission_halt,   % as SWI's at_halt hooks call it
          cancel_halt(_), true),
    ( strata_driver:halt_requested(_) -> Requested = true ; Requested = false ),
    catch(strata_driver:halt_check, E, true).

test(stops_become_aborted_when_the_host_asks,
     [setup(open_test_mission(M)),
      cleanup(( retractall(strata_driver:active(_)), retractall(strata_driver:uncatchable_stops),
                retractall(strata_driver:stop_cause(_)), close_mission(M) )),
      true(Out-Cause == '$aborted'-inference_limit_exceeded)]) :-
    retractall(strata_driver:stop_cause(_)),
    asserta(strata_driver:active(M)),
    assertz(strata_driver:uncatchable_stops),
    user:prolog_exception_hook(inference_limit_exceeded, Out, _, _),
    strata_driver:stop_cause(Cause).

test(other_exceptions_stay_catchable,
     [setup(open_test_mission(M)),
      cleanup(( retractall(strata_driver:active(_)), retractall(strata_driver:uncatchable_stops),
                close_mission(M) )),
      fail]) :-
    asserta(strata_driver:active(M)),
    assertz(strata_driver:uncatchable_stops),
    user:prolog_exception_hook(error(type_error(integer, a), _), _, _, _).

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
