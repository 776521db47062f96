/*  The PROLOG Strategic level's driver (docs/prolog.md).

    Compiled into the strata binary and loaded once per process. It loads a
    mission's rules into a module of their own, defines the vehicle
    primitives there from the catalogue, checks the rules before they run,
    runs mission/0 and says how it ended. Two parts are loaded into this
    module after this file: driver_load.pl (loading and checking the rules)
    and driver_sandbox.pl (what the rules may do). The host (C++) provides:

      '$strata_call'(+Name, +Args, -Answer)  calls a primitive and yields
                                             until the vehicle answers 1 or 0
      '$strata_report'(+Name, +Args)         a REPORT: sent, not waited for
      '$strata_phase'(+Event, +Phase)        tells observers a phase started
                                             (start) or ended (end(Exit))
      '$strata_guards_open'(+Specs, -Scope)  a guarded scope starts: the host
                                             polls its guards (docs/prolog.md §8)
      '$strata_guards_close'(+Scope, -Trip)  it ends: none, or tripped(Guard)
*/
:- module(strata_driver,
          [ open_mission/2,          % -Module, +PrimitiveSpecs
            load_mission/2,          % +Module, +File
            load_mission/3,          % +Module, +File, +InferenceBudget
            check_mission/2,         % +Module, -Problems
            run_mission/2,           % +Module, +InferenceLimit
            mission_outcome/2,       % +Module, -Outcome
            mission_data/2,          % +Module, -File
            stop_cause/1,            % -Exception: what stopped the rules
            close_mission/1,         % +Module
            unlimited/0
          ]).
% Defined by driver_load.pl, loaded into this module after this file: so
% declared here, or the end of this file's load says they are not defined.
:- multifile load_mission/2,
             load_mission/3,
             check_mission/2.

:- use_module(library(lists)).
:- use_module(library(apply)).
:- use_module(library(aggregate)).
:- use_module(library(readutil)).
:- use_module(library(solution_sequences)).
:- use_module(library(prolog_wrap)).
:- use_module(library(sandbox)).
:- use_module(library(occurs)).
:- use_module(library(error), [must_be/2]).

% The libraries the driver loads call some predicates of other libraries
% through autoload declarations, which SWI-Prolog resolves at the first
% call by reading the other library's file for its exports (autoload/1):
% about 2.5 ms of the first load and check of a process (`strata check`),
% although every one of these libraries is loaded already (the precompiled
% driver, driver_libraries.pl). The links those first calls make are made
% here instead, from the loaded modules: the same imports, at once. A link
% whose modules or predicate are not there (another SWI-Prolog, the plunit
% tests' load order) is left to the autoloader, as before.
library_link(solution_sequences, nb_set, empty_nb_set/1).   % distinct/1,2
library_link(solution_sequences, nb_set, add_nb_set/3).
library_link(nb_set, lists, member/2).
library_link(lists, error, must_be/2).                      % append/2 (check_mission/2)
library_link(prolog_codewalk, swi_option, meta_options/3).  % prolog_walk_code/1
library_link(prolog_codewalk, error, must_be/2).
library_link(prolog_codewalk, prolog_debug, debug/3).
library_link(prolog_codewalk, prolog_metainference, inferred_meta_predicate/2).
library_link(swi_option, error, must_be/2).

link_library_predicate(Module, From, Name/Arity) :-
    (   current_module(Module),
        current_module(From),
        current_predicate(From:Name/Arity),
        functor(Head, Name, Arity),
        % Not defined there (a call names it, the autoloader has not run):
        % current_predicate/1 would say it is.
        \+ '$get_predicate_attribute'(Module:Head, defined, 1),
        \+ '$get_predicate_attribute'(Module:Head, imported, _)
    ->  Module:import(From:Name/Arity)
    ;   true
    ).

:- forall(library_link(Module, From, PI), link_library_predicate(Module, From, PI)).

:- dynamic loading/1,            % Module: collecting load messages for it
           load_message/5,       % Kind, File, Line, Column, Text
           inference_budget/1,   % inferences allowed between primitive calls
           primitive_predicate/2, % Module, Name/Arity: defined from the catalogue
           ood_names/3,          % Module, Arity, Names: the OOD primitives of ood/Arity
           active/1,             % Module: loading or running (the hooks act)
           stop_cause/1,         % the exception that stopped the rules
           halt_requested/1,     % File:Line, when the rules called system:halt
           uncatchable_stops/0,  % the host's: stops become '$aborted'
           mission_root/2,       % Module, Folder: the folder of the mission's file
           stop_place/2,         % File, Line: where a stop while loading happened
           flag_baseline/2,      % Flag, Value: as before any mission (restore_flags/0)
           load_effect/2,        % Module, Directive: its load ran more than declarations
           include_refused/2,    % Module, Spec: an include/1 refused as read, not to be reported twice
           load_resolution/2.    % Module, Resolution: a file name its load resolved

                 /*******************************
                 *   THE MISSION'S OWN MODULE   *
                 *******************************/

%!  open_mission(-Module, +Primitives) is det.
%
%   Creates a fresh temporary module for one mission and defines in it one
%   predicate per primitive. Primitives is a list of
%   primitive(Name, Kind, MinArgs, MaxArgs) with Kind exec, ask, ood or
%   report, as in the catalogue. The rules call them as Figure 10 does:
%   exec_Name(A1, ..., X), ask_Name(A1, ..., X), ood('Name', A1, ..., X) and
%   Name(A1, ...) for a report; X is unified with the answer, 1 or 0.

open_mission(Module, Primitives) :-
    flag(strata_mission, N, N + 1),
    format(atom(Module), 'strata_mission_~d', [N]),
    set_module(Module:class(temporary)),
    guard_halt(Module),
    forall(member(P, Primitives), define_primitive(Module, P)),
    (   setof(A, ood_arity(Primitives, A), Arities)
    ->  forall(member(A, Arities), define_ood(Module, Primitives, A))
    ;   true
    ).

% halt/0,1 in the rules end the mission, not the host: they throw
% strata_halt and strata_halt(Code), which the host turns into the end.
% must_be/2 is named with its module: the mission's module does not import
% it, and the check's walk of halt/1 would otherwise look it up in
% SWI-Prolog's autoload index, which the first check of a process then
% reads from its text (about 3 ms of `strata check`).
guard_halt(M) :-
    redefine_system_predicate(M:halt),
    M:assertz((halt :- throw(strata_halt))),
    redefine_system_predicate(M:halt(_)),
    M:assertz((halt(Code) :- error:must_be(integer, Code), throw(strata_halt(Code)))),
    compile_predicates(M:[halt/0, halt/1]).

% system:halt/0,1 called by the rules (module-qualified, past the guard
% above) while a mission is active: wrapped to throw the same, at once.
% Letting SWI-Prolog start to halt and cancelling it in an at_halt hook
% (below) is only the fallback: a cancelled halt leaves the engine's trace
% suspension one off, after which SWI no longer calls
% user:prolog_exception_hook/4 for the host's queries (so the rules could
% catch what must stop them: the inference limit, the interrupt), and after
% ten cancelled halts SWI halts anyway.
:- wrap_predicate(system:halt, strata_halt, Halt,
                  (   strata_driver:active(_) -> throw(strata_halt) ; Halt )).
:- wrap_predicate(system:halt(Code), strata_halt, Halt,
                  (   strata_driver:active(_)
                  ->  must_be(integer, Code),
                      throw(strata_halt(Code))
                  ;   Halt
                  )).

% sleep/1, the one predicate the sandbox allows that waits without
% inferences, is refused while a mission loads, at the directive's place:
% directives run at check time and have no reason to wait. The rules'
% clauses may call it when they run (interrupts reach it then).
:- wrap_predicate(system:sleep(_), strata_load_sleep, Sleep,
                  (   strata_driver:loading(_)
                  ->  strata_driver:note_stop_place,
                      strata_driver:refuse(sleep/1, "sleep/1 while the rules load: directives run \c
                                            at check time, and cannot wait", [])
                  ;   Sleep
                  )).

% The place of a stop while loading: the load is unwound past the
% directive before load_exception/1 sees the stop.
note_stop_place :-
    (   stop_place(_, _) -> true
    ;   source_location(F, L) -> assertz(stop_place(F, L))
    ;   true
    ).

% What reaches SWI's halt all the same while a mission is active is
% cancelled, remembered, and turned into strata_halt at the next primitive
% call or the end of the rules.
:- at_halt(strata_driver:cancel_mission_halt).

cancel_mission_halt :-
    active(_),
    !,
    (   source_location(File, Line) -> true ; File = '', Line = 0 ),
    (   halt_requested(_) -> true ; assertz(halt_requested(File:Line)) ),
    cancel_halt('a mission cannot end the strata process').
cancel_mission_halt.

halt_check :-
    (   halt_requested(_) -> throw(strata_halt) ; true ).

% While a mission loads or runs, what must end it cannot be caught by the
% rules (a catch-all around a loop would otherwise run for ever): the
% exception becomes '$aborted', which a recovery goal cannot stop, and the
% first cause is kept for the host (stop_cause/1). The host turns this on
% (uncatchable_stops/0); plunit tests leave it off and see the exceptions.
% SWI calls the hook only for queries not opened with PL_Q_NODEBUG.
:- multifile user:prolog_exception_hook/4.
:- dynamic user:prolog_exception_hook/4.
user:prolog_exception_hook(E, '$aborted', _, _) :-
    nonvar(E),
    E \== '$aborted',
    strata_driver:uncatchable_stops,
    strata_driver:active(_),
    strata_driver:stops_the_mission(E),
    (   strata_driver:loading(_) -> strata_driver:note_stop_place ; true ),
    (   strata_driver:stop_cause(_) -> true ; assertz(strata_driver:stop_cause(E)) ).

% Our exceptions, as people read them (load messages, uncaught errors).
:- multifile prolog:message//1, prolog:error_message//1.
prolog:message(strata_error(Text)) --> [ '~w'-[Text] ].
prolog:message(strata_halt) --> [ 'the rules called halt/0' ].
prolog:message(strata_halt(Code)) --> [ 'the rules called halt(~q)'-[Code] ].
prolog:message(strata_cancelled) --> [ 'the mission was cancelled' ].
prolog:message(strata_interrupted) --> [ 'the mission was interrupted' ].
prolog:error_message(strata_refused(_, Text)) --> [ '~w'-[Text] ].

stops_the_mission(inference_limit_exceeded).
stops_the_mission(strata_halt).
stops_the_mission(strata_halt(_)).
stops_the_mission(strata_cancelled).
stops_the_mission(strata_interrupted).   % the host's interrupt (prolog/interrupt.h)
stops_the_mission(error(resource_error(_), _)).
stops_the_mission(error(strata_refused(sleep/1, _), _)).  % a directive cannot catch it and wait on

reset_stop :-
    retractall(stop_place(_, _)),
    retractall(stop_cause(_)),
    retractall(halt_requested(_)).

define_primitive(_, primitive(_, ood, _, _)) :- !.
define_primitive(M, primitive(Name, Kind, Min, Max)) :-
    forall(between(Min, Max, N), define_primitive(M, Name, Kind, N)).

define_primitive(M, Name, Kind, N) :-
    length(Args, N),
    (   Kind == report
    ->  Head =.. [Name|Args],
        Body = strata_driver:call_report(Name, Args)
    ;   atomic_list_concat([Kind, '_', Name], Functor),
        append(Args, [X], HeadArgs),
        Head =.. [Functor|HeadArgs],
        Body = strata_driver:call_primitive(Name, Args, X)
    ),
    functor(Head, F, A),
    M:assertz((Head :- Body)),
    compile_predicates(M:[F/A]),
    assertz(primitive_predicate(M, F/A)).

ood_arity(Primitives, A) :-
    member(primitive(_, ood, Min, Max), Primitives),
    between(Min, Max, N),
    A is N + 2.

% ood('Name', A1, ..., X): one predicate for every OOD primitive of that arity.
define_ood(M, Primitives, A) :-
    N is A - 2,
    length(Args, N),
    append([Name|Args], [X], HeadArgs),
    Head =.. [ood|HeadArgs],
    findall(P, ( member(primitive(P, ood, Min, Max), Primitives),
                 between(Min, Max, N) ), Names),
    M:assertz((Head :- strata_driver:call_ood(Names, Name, Args, X))),
    compile_predicates(M:[ood/A]),
    assertz(primitive_predicate(M, ood/A)),
    assertz(ood_names(M, A, Names)).

call_ood(Names, Name, Args, X) :-
    must_be(atom, Name),
    (   memberchk(Name, Names)
    ->  call_primitive(Name, Args, X)
    ;   length(Args, N),
        throw(error(existence_error(ood_primitive, Name/N), _))
    ).

call_primitive(Name, Args, X) :-
    halt_check,
    '$strata_call'(Name, Args, Answer),
    rearm,
    X = Answer.

% A report is text: numbers and terms are written as print/1 would.
call_report(Name, Args) :-
    halt_check,
    maplist(report_text, Args, Texts),
    '$strata_report'(Name, Texts).

report_text(A, A) :- atom(A), !.
report_text(S, S) :- string(S), !.
report_text(T, S) :- format(string(S), '~p', [T]).

%!  close_mission(+Module) is det.
%
%   Forgets the mission: its module, its clauses and the files loaded into
%   it (so the same files can be loaded again into a new module).

close_mission(Module) :-
    unlimited,
    retractall(primitive_predicate(Module, _)),
    retractall(ood_names(Module, _, _)),
    retractall(load_effect(Module, _)),
    retractall(load_resolution(Module, _)),
    retractall(system:'$load_context_module'(_, Module, _)),
    catch('$destroy_module'(Module), _, true).

                 /*******************************
                 *           RUNNING            *
                 *******************************/

%!  run_mission(+Module, +InferenceLimit) is semidet.
%
%   Runs Module:mission once. Between two primitive calls the rules may use
%   at most InferenceLimit inferences; past it they raise
%   inference_limit_exceeded (an endless loop that never acts).
%   execute_phase/1, when the rules define it, is wrapped to tell the host
%   when each phase starts and ends. Arithmetic's random/1 and random_float
%   (and library(random) with them) start from the same seed at every run,
%   so that the same inputs make the same run; the sandbox keeps the rules
%   from reseeding.

run_mission(Module, Limit) :-
    retractall(inference_budget(_)),
    assertz(inference_budget(Limit)),
    set_random(seed(1)),
    restore_flags,
    reset_stop,
    wrap_phases(Module),
    mission_guards(Module, Guards),
    (   setup_call_cleanup(
            asserta(active(Module), Ref),
            ( rearm, run_guarded(Module, Guards, Module:mission), ! ),
            ( erase(Ref), restore_flags ))
    ->  unlimited,
        halt_check
    ;   unlimited,
        halt_check,             % a cancelled system:halt made mission/0 fail
        fail
    ).

%!  restore_flags is det.
%
%   The rules may set the Prolog flags library(sandbox) allows
%   (safe_prolog_flag/2: occurs_check, double_quotes, the float and
%   rational arithmetic flags, ...) and lower the stack limit. Set while the
%   rules run, these are the process's, not the mission module's: left as
%   the rules set them, they would change how the next mission loads
%   (double_quotes) and runs (occurs_check, a smaller stack) in a campaign's
%   worker or the studio. Each is put back to its value from before the
%   first mission, before every load and every run, and when a run ends.

restore_flags :-
    (   flag_baseline(_, _)
    ->  true
    ;   forall(( distinct(F, sandbox:safe_prolog_flag(F, _)), current_prolog_flag(F, V) ),
               assertz(flag_baseline(F, V))),
        current_prolog_flag(stack_limit, L),
        assertz(flag_baseline(stack_limit, L))
    ),
    forall(flag_baseline(F, V),
           (   current_prolog_flag(F, V) -> true ; set_prolog_flag(F, V) )).

% Kept rules (driver_keep.pl) are wrapped already, by their first run.
wrap_phases(Module) :-
    (   current_predicate(Module:execute_phase/1),
        \+ current_predicate_wrapper(Module:execute_phase(_), strata_phase, _, _)
    ->  wrap_predicate(Module:execute_phase(P), strata_phase, W,
                       strata_driver:run_phase(Module, P, W))
    ;   true
    ).

run_phase(Module, Phase, Wrapped) :-
    '$strata_phase'(start, Phase),
    phase_guards(Module, Phase, Guards),
    (   Guards == []
    ->  Body = Wrapped
    ;   Body = run_guarded(Module, Guards, Wrapped)
    ),
    (   catch(call(Body), E, ( phase_raised(Phase, E), throw(E) ))
    *-> phase_exit(Module, Phase, Exit),
        '$strata_phase'(end(Exit), Phase)
    ;   '$strata_phase'(end(failed), Phase),
        fail
    ).

% An error leaving a phase ends it as failed (the rules may catch the error
% and go on). What ends the mission ends the phase with it: the host closes
% it as cancelled; so does the trip of a guard of an enclosing scope.
phase_raised(Phase, E) :-
    (   ( E == '$aborted' ; stops_the_mission(E) ; E = strata_guard_trip(_, _) )
    ->  true
    ;   '$strata_phase'(end(failed), Phase)
    ).

% Figure 10's phases say how they ended with complete(P) or abort(P).
phase_exit(Module, Phase, Exit) :-
    (   holds(Module, complete(Phase)) -> Exit = complete
    ;   holds(Module, abort(Phase))    -> Exit = abort
    ;   Exit = done
    ).

holds(Module, Goal) :-
    functor(Goal, N, A),
    current_predicate(Module:N/A),
    \+ \+ catch(Module:Goal, _, fail).

                 /*******************************
                 *            GUARDS            *
                 *******************************/

% The rules' guards (docs/prolog.md §8): guard(Name, Period, Condition,
% Handler) facts for the whole mission, phase_guard(Phase, Name, Period,
% Condition, Handler) facts for the phases whose term unifies with Phase;
% in declaration order. driver_check.pl checked them at load, and refuses
% them dynamic: a guard the rules asserted as they run is never read (its
% handler would be a goal nobody checked).

mission_guards(Module, Guards) :-
    (   static_facts(Module, guard/4)
    ->  findall(guard(N, P, C, H), Module:guard(N, P, C, H), Guards)
    ;   Guards = []
    ).

phase_guards(Module, Phase, Guards) :-
    (   static_facts(Module, phase_guard/5)
    ->  findall(guard(N, P, C, H), Module:phase_guard(Phase, N, P, C, H), Guards)
    ;   Guards = []
    ).

static_facts(Module, Name/Arity) :-
    current_predicate(Module:Name/Arity),
    functor(Head, Name, Arity),
    \+ predicate_property(Module:Head, dynamic),
    \+ predicate_property(Module:Head, imported_from(_)).

%!  run_guarded(+Module, +Guards, :Goal) is semidet.
%
%   Runs Goal once while the host polls Guards. When one trips, the host
%   raises strata_guard_trip(Scope, Guard) in the rules (at the primitive
%   call they wait in): Goal is unwound, its cleanup handlers run, and the
%   guard's handler runs in Goal's place; its success or failure is the
%   scope's. Between the trip and the handler every primitive call raises
%   the trip again (the host makes none), so rules that catch it cannot go
%   on: if Goal ends all the same, the handler runs then. The trip of an
%   enclosing scope passes through (outer wins).

run_guarded(_, [], Goal) :- !,
    once(Goal).
run_guarded(Module, Guards, Goal) :-
    maplist(guard_spec, Guards, Specs),
    '$strata_guards_open'(Specs, Scope),
    catch(( once(Goal) -> Ran = true ; Ran = false ),
          E,
          guard_caught(E, Scope, Ran)),
    '$strata_guards_close'(Scope, Trip),
    (   Trip = tripped(Name)
    ->  memberchk(guard(Name, _, _, Handler), Guards),
        once(Module:Handler)
    ;   Ran == true
    ).

% The scope's own trip ends its Goal; any other exception closes the scope
% and goes on.
guard_caught(E, Scope, tripped) :-
    nonvar(E),
    E = strata_guard_trip(Scope, _),
    !.
guard_caught(E, Scope, _) :-
    '$strata_guards_close'(Scope, _),
    throw(E).

guard_spec(guard(Name, Period, Condition, _), spec(Name, Period, Terms)) :-
    maplist(guard_term, Condition, Terms).

guard_term(not(Q), t(Name, Args, true)) :- !,
    Q =.. [Name|Args].
guard_term(Q, t(Name, Args, false)) :-
    Q =.. [Name|Args].

% The inference limit is reset after every primitive call: SWI's own
% '$inference_limit'/2 only lowers it, so restore "none" first.
rearm :-
    inference_budget(Limit),
    !,
    unlimited,
    system:'$inference_limit'(Limit, _).
rearm.

unlimited :-
    (   system:'$inference_limit_false'(0x7fffffffffffffff) -> true ; true ).

%!  mission_outcome(+Module, -Outcome) is det.
%
%   After mission/0: aborted when the rules left current_phase(mission_abort)
%   (Figure 10's `done`), completed otherwise.

mission_outcome(Module, Outcome) :-
    (   holds(Module, current_phase(mission_abort))
    ->  Outcome = aborted
    ;   Outcome = completed
    ).

%!  mission_data(+Module, -File) is semidet.
%
%   The mission data file the rules name with a mission_data/1 fact (the
%   CORAL mission's `data "..."`), as written: relative to the rules' folder.

mission_data(Module, File) :-
    current_predicate(Module:mission_data/1),
    catch(( Module:mission_data(File0), text_to_string(File0, File) ), _, fail),
    !.
