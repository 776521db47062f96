/*  Shared support for the plunit tests of the PROLOG Strategic level's
    driver (driver.pl): driver_test_load.pl and driver_test_run.pl load it.

    swipl alone has no host, so this file defines stand-ins for the
    predicates the C++ host normally provides in module strata_driver: they
    record what the rules did as event/1 facts and answer primitive calls
    from a scripted queue (1 once the queue is empty). It also holds the
    helpers the tests share: a test catalogue of primitives, opening and
    closing a mission, and writing rule files to temporary files at test
    time.
*/
:- module(strata_driver_test_support,
          [ script/1,                % +Answers
            events/1,                % -Events
            primitives/1,            % -PrimitiveSpecs
            open_test_mission/1,     % -Module
            rules_file/2,            % +Lines, -File
            mission_from/3,          % +Lines, -Module, -File
            done_with/2,             % +Module, +File
            load_messages/1,         % -Messages
            contains/2,              % +Text, +Part
            busy/0
          ]).
:- use_module(library(lists)).
:- use_module(library(apply)).

:- prolog_load_context(directory, Dir),
   directory_file_path(Dir, 'driver_check.pl', Check),
   use_module(Check, []),
   directory_file_path(Dir, 'driver.pl', Driver),
   use_module(Driver),
   forall(member(Part, ['driver_load.pl', 'driver_sandbox.pl']),
          (   directory_file_path(Dir, Part, File),
              load_files(strata_driver:File, [])
          )).

                 /*******************************
                 *      THE HOST'S STAND-INS    *
                 *******************************/

:- dynamic event/1,              % call(Name, Args), report(Name, Args), phase(Event, Phase),
                                 % guards(Specs), guards_closed(Scope)
           answer_queue/1.       % the answers still to give, in order

strata_driver:'$strata_call'(Name, Args, Answer) :-
    strata_driver_test_support:host_call(Name, Args, Answer).
strata_driver:'$strata_report'(Name, Args) :-
    strata_driver_test_support:host_event(report(Name, Args)).
strata_driver:'$strata_phase'(Event, Phase) :-
    strata_driver_test_support:host_event(phase(Event, Phase)).
strata_driver:'$strata_guards_open'(Specs, 1) :-
    strata_driver_test_support:host_event(guards(Specs)).
strata_driver:'$strata_guards_close'(Scope, none) :-
    strata_driver_test_support:host_event(guards_closed(Scope)).

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
