/*  plunit tests for the check's memory of rules that passed
    (driver_check.pl, passed_check/2): the same rules, loaded again in the
    same process, are not walked and sandbox-checked again; rules that
    differ in anything the check sees are.

    Run from any folder:

        swipl --no-packs -q -g "(run_tests -> halt(0) ; halt(1))" -t halt src/strategic/prolog/driver_test_cache.pl

    The number of sandbox checks made is counted by a wrapper on
    strata_driver_check:sandbox_problems/2, put on for these tests only.
*/
:- module(strata_driver_test_cache, []).
:- use_module(library(plunit)).
:- use_module(library(lists)).
:- use_module(library(aggregate)).
:- use_module(library(prolog_wrap)).

:- prolog_load_context(directory, Dir),
   directory_file_path(Dir, 'driver.pl', Driver),
   use_module(Driver),
   directory_file_path(Dir, 'driver_test_support.pl', Support),
   use_module(Support).

:- dynamic checks_made/1.
checks_made(0).

:- wrap_predicate(strata_driver_check:sandbox_problems(M, P), strata_test_count, Check,
                  ( strata_driver_test_cache:count_check, Check )),
   ignore((M = M, P = P)).

count_check :-
    retract(checks_made(N)),
    N1 is N + 1,
    assertz(checks_made(N1)).

% Loads Lines into a fresh module and checks them: Problems, and how many
% sandbox checks that made (0 or 1).
checked(Lines, Problems, Checks) :-
    rules_file(Lines, File),
    checked_file(File, Problems, Checks),
    catch(delete_file(File), _, true).

checked_file(File, Problems, Checks) :-
    checks_made(Before),
    open_test_mission(M),
    load_mission(M, File),
    check_mission(M, Problems),
    close_mission(M),
    checks_made(After),
    Checks is After - Before.

% Forgets the rules that passed; and makes a check first, since the first
% check of a process keeps nothing.
forget :-
    retractall(strata_driver_check:passed_check(_, _)),
    checked(["mission."], _, _).

:- begin_tests(check_memory, [setup(forget), cleanup(forget)]).

test(the_same_rules_are_checked_once) :-
    Lines = ["mission :- helper(X), exec_submerge(X).", "helper(1)."],
    checked(Lines, P1, C1),
    checked(Lines, P2, C2),
    assertion(P1 == []), assertion(C1 == 1),
    assertion(P2 == []), assertion(C2 == 0).

test(an_edited_file_with_a_hostile_clause_is_refused) :-
    rules_file(["mission :- helper.", "helper :- write(ok)."], File),
    checked_file(File, P1, _),
    assertion(P1 == []),
    setup_call_cleanup(open(File, write, Out),
                       format(Out, "mission :- helper.~nhelper :- write(ok), shell(ls).~n", []),
                       close(Out)),
    checked_file(File, P2, C2),
    catch(delete_file(File), _, true),
    assertion(C2 == 1),
    assertion(memberchk(problem(_, 2:_, _), P2)).

test(rules_that_failed_are_checked_every_time) :-
    rules_file(["mission :- shell(ls)."], File),
    checked_file(File, P1, C1),
    checked_file(File, P2, C2),
    catch(delete_file(File), _, true),
    assertion(P1 = [problem(_, 1:_, _)]), assertion(C1 == 1),
    assertion(P2 == P1), assertion(C2 == 1).

test(a_different_catalogue_is_checked_again) :-
    Lines = ["mission :- exec_submerge(_)."],
    checked(Lines, _, _),
    rules_file(Lines, File),
    checks_made(Before),
    open_mission(M, [primitive(sleep, exec, 1, 1)]),
    load_mission(M, File),
    check_mission(M, Problems),
    close_mission(M),
    catch(delete_file(File), _, true),
    checks_made(After),
    assertion(After =:= Before + 1),
    assertion(Problems = [problem(_, _, _)]).

% The rules' own module name means something else in the next mission's
% module: such rules are not remembered.
test(rules_naming_their_own_module_are_checked_every_time) :-
    open_test_mission(M),
    format(string(Line), "mine(~q).", [M]),
    rules_file(["mission :- mine(_).", Line], File),
    aggregate_all(count, strata_driver_check:passed_check(_, _), Before),
    load_mission(M, File),
    check_mission(M, Problems),
    close_mission(M),
    catch(delete_file(File), _, true),
    aggregate_all(count, strata_driver_check:passed_check(_, _), After),
    assertion(Problems == []),
    assertion(After == Before).

:- end_tests(check_memory).
