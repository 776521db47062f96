/*  The PROLOG Strategic level's driver (docs/prolog.md).

    Compiled into the strata binary and loaded once per process. It loads a
    mission's rules into a module of their own, defines the vehicle
    primitives there from the catalogue, checks the rules before they run,
    runs mission/0 and says how it ended. The host (C++) provides:

      '$strata_call'(+Name, +Args, -Answer)  calls a primitive and yields
                                             until the vehicle answers 1 or 0
      '$strata_report'(+Name, +Args)         a REPORT: sent, not waited for
      '$strata_phase'(+Event, +Phase)        tells observers a phase started
                                             (start) or ended (end(Exit))
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
:- use_module(library(lists)).
:- use_module(library(apply)).
:- use_module(library(aggregate)).
:- use_module(library(readutil)).
:- use_module(library(solution_sequences)).
:- use_module(library(prolog_wrap)).
:- use_module(library(sandbox)).
:- use_module(library(occurs)).

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
           flag_baseline/2.      % Flag, Value: as before any mission (restore_flags/0)

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
guard_halt(M) :-
    redefine_system_predicate(M:halt),
    M:assertz((halt :- throw(strata_halt))),
    redefine_system_predicate(M:halt(_)),
    M:assertz((halt(Code) :- must_be(integer, Code), throw(strata_halt(Code)))),
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
    retractall(system:'$load_context_module'(_, Module, _)),
    catch('$destroy_module'(Module), _, true).

                 /*******************************
                 *          LOADING             *
                 *******************************/

%!  load_mission(+Module, +File) is det.
%
%   Loads File into Module. Errors and warnings printed while loading are
%   kept (not printed) as load_message/5 facts, with their file and line.

load_mission(Module, File) :-
    load_budget(Budget),
    load_mission(Module, File, Budget).

%!  load_mission(+Module, +File, +InferenceBudget) is det.
%
%   As load_mission/2, the directives getting InferenceBudget inferences in
%   all (the host's --load-inference-limit).

load_mission(Module, File, Budget) :-
    restore_flags,
    retractall(load_message(_, _, _, _, _)),
    reset_stop,
    retractall(mission_root(Module, _)),
    file_directory_name(File, Root),
    assertz(mission_root(Module, Root)),
    % sandboxed(true): SWI checks every directive with
    % prolog:sandbox_allowed_directive/1 (library(sandbox), extended below)
    % before it runs it, and calls no term or goal expansion hook; files the
    % rules load are loaded sandboxed too.
    (   scan_problem(File, Line, Column, Text)
    ->  assertz(load_message(error, File, Line, Column, Text))
    ;   setup_call_cleanup(
            ( asserta(loading(Module), Ref), asserta(active(Module), Active),
              unlimited, system:'$inference_limit'(Budget, _) ),
            catch(load_mission_file(Module, File, [if(true), sandboxed(true)]), E, load_exception(E)),
            ( unlimited, erase(Active), erase(Ref) ))
    ),
    (   halt_requested(F:L)
    ->  assertz(load_message(error, F, L, 0, "the rules called halt while loading"))
    ;   true
    ),
    forall(distinct(Loaded, ( Loaded = File
                            ; source_file_property(Loaded, load_context(Module, _, _))
                            )),
           module_file_check(Loaded)).

% A mission's files are plain rules: a module file would keep its clauses
% out of the mission's module, where the primitives and the check are.
module_file_check(File) :-
    (   source_file_property(File, module(M)),
        \+ module_property(M, class(library))   % use_module(library(lists))
    ->  format(string(Text), "a module file (module ~w): a mission's files are plain rules, \c
                              without :- module/2", [M]),
        assertz(load_message(error, File, 1, 0, Text))
    ;   true
    ).

% A mission's file is loaded from a stream the driver opens: SWI-Prolog
% 9.0.4 loads a file named by its path inside sig_atomic/1 (init.pl,
% '$mt_load_file'/4), where no signal reaches a directive, so the host's
% wall-clock limit (mission.cpp, TimeLimit) could not end one that computes
% for minutes within its inference budget (`X is 7^(7^9)` a hundred times);
% a stream is loaded without it ('$load_file_e'/3). The mission's own files
% that it consults come here too, through user:prolog_load_file/2.
load_mission_file(Module, File, Options) :-
    setup_call_cleanup(
        open(File, read, In, [encoding(utf8)]),
        load_files(Module:File, [stream(In)|Options]),
        close(In)).

:- multifile user:prolog_load_file/2.
:- dynamic user:prolog_load_file/2.
user:prolog_load_file(Module:Spec, Options) :-
    loading(Mission),
    \+ memberchk(stream(_), Options),
    (   atom(Spec) ; string(Spec) ),
    prolog_load_context(directory, Dir),
    absolute_file_name(Spec, Abs, [ file_type(prolog), relative_to(Dir),
                                    access(read), file_errors(fail) ]),
    mission_file(Mission, Abs),
    !,
    load_mission_file(Module, Abs, Options).

% Abs is one of the files a mission may load: a .pl file in the folder of
% the mission's file or in a folder beside it (consult_directive/2).
mission_file(M, Abs) :-
    file_name_extension(_, pl, Abs),
    mission_root(M, Root),   % Root's parent holds Root, and the folders beside it
    file_directory_name(Root, Parent),
    Parent \== '/',
    atom_concat(Parent, '/', Under),            % not /m/tank_evil for /m/tank
    sub_atom(Abs, 0, _, _, Under).

% Directives get this many inferences in all: a directive that loops ends.
load_budget(50000000).

% What SWI-Prolog's reader must not see (a term nested too deep, a line too
% long: mission.cpp, scan_rules_text()), found by the host before a file is
% read. Without the host (plunit), nothing is found.
scan_problem(File, Line, Column, Text) :-
    current_predicate(strata_driver:'$strata_scan'/2),
    '$strata_scan'(File, problem(Line, Column, Text)).


load_exception('$aborted') :-
    stop_cause(Cause),
    !,
    load_exception(Cause).
load_exception(E) :-
    refusal(E, Culprit, Text),
    !,
    (   source_location(F0, L0) -> true
    ;   stop_place(F0, L0) -> true
    ;   F0 = '', L0 = 0
    ),
    culprit_place(F0, L0, 0, Culprit, F, L, C),
    assertz(load_message(error, F, L, C, Text)).
load_exception(E) :-
    stops_the_mission(E),
    !,
    (   source_location(F, L) -> true
    ;   stop_place(F, L) -> true
    ;   F = '', L = 0
    ),
    stop_text(E, Text),
    assertz(load_message(error, F, L, 0, Text)).
load_exception(E) :-
    message_text(E, error, Text),
    (   source_location(F, L) -> true ; F = '', L = 0 ),
    assertz(load_message(error, F, L, 0, Text)).

stop_text(inference_limit_exceeded, "the load used up its inferences (--load-inference-limit): \c
                                     a directive that loops, or rules too large?") :- !.
stop_text(strata_halt, "the rules called halt while loading") :- !.
stop_text(strata_interrupted, "loading took longer than its time limit (--load-time-limit): \c
                               a directive that computes, waits or loops?") :- !.
stop_text(strata_halt(_), "the rules called halt while loading") :- !.
stop_text(error(resource_error(R), _), Text) :- !,
    format(string(Text), "a directive ran out of ~w while loading (endless recursion?)", [R]).
stop_text(E, Text) :-
    format(string(Text), "loading stopped: ~q", [E]).

:- multifile user:message_hook/3.
user:message_hook(Term, Kind, _Lines) :-
    loading(_),
    (   Kind == error ; Kind == warning ),
    !,
    % A directive that hit the load budget: the rest runs without it. Any
    % other message (a warning about the file's encoding, a singleton)
    % leaves the budget armed: lifting it there let `:- loop.` run for ever
    % after a warning (found by fuzz/prolog_fuzz.cpp).
    (   stops_the_mission(Term) -> unlimited ; true ),
    message_location(Term, File0, Line0, Column0),
    (   refusal(Term, Culprit, Text)
    ->  Recorded = error,
        culprit_place(File0, Line0, Column0, Culprit, File, Line, Column)
    ;   File = File0, Line = Line0, Column = Column0,
        message_record(Term, Kind, Recorded, Text)
    ),
    assertz(load_message(Recorded, File, Line, Column, Text)).

message_record(Term, _, error, Text) :-
    stops_the_mission(Term),
    !,
    stop_text(Term, Text).
message_record(Term, Kind, Recorded, Text) :-
    % The place is given apart: translate the message without it.
    (   Term = error(Formal, Context),
        subsumes_term(file(_, _, _, _), Context)
    ->  message_text(error(Formal, _), Kind, Text0)
    ;   message_text(Term, Kind, Text0)
    ),
    message_kind(Term, Kind, Recorded),
    message_hint(Term, Hint),
    string_concat(Text0, Hint, Text).

% Loading a file that defines clauses another file already defined wipes
% the first file's clauses (tank.pl and phase2.pl both add to
% execute_phase/1): an error, not SWI's warning. So is redefining a
% primitive or halt/0,1.
message_kind(redefined_procedure(_, _), _, error) :- !.
message_kind(_, Kind, Kind).

message_hint(redefined_procedure(_, M:Name/Arity), Hint) :-
    reserved(M, Name/Arity),
    !,
    format(string(Hint), ": ~w/~d is Strata's, the rules cannot redefine it", [Name, Arity]).
message_hint(redefined_procedure(_, _:Name/Arity), Hint) :- !,
    format(string(Hint), ": declare `:- multifile ~w/~d.` in the file that loads the \c
                          others, before it loads them", [Name, Arity]).
message_hint(_, "").

% The predicates Strata defines in a mission's module.
reserved(_, halt/0).
reserved(_, halt/1).
reserved(M, PI) :- primitive_predicate(M, PI).


message_location(error(_, Context), File, Line, Column) :-
    subsumes_term(file(_, _, _, _), Context),
    Context = file(File, Line, LinePos, _),
    integer(LinePos),
    !,
    Column is LinePos + 1.
message_location(_, File, Line, 0) :-
    source_location(File, Line),
    !.
message_location(_, File, Line, 0) :-
    prolog_load_context(file, File),
    prolog_load_context(term_position, Pos),
    stream_position_data(line_count, Pos, Line),
    !.
message_location(_, '', 0, 0).

message_text(Term, _Kind, Text) :-
    catch(( '$messages':translate_message(Term, Lines, []),
            with_output_to(string(Text0),
                           print_message_lines(current_output, '', Lines)),
            normalize_space(string(Text), Text0)
          ), _, fail),
    !.
message_text(Term, _, Text) :-
    format(string(Text), '~q', [Term]).

%!  check_mission(+Module, -Problems) is det.
%
%   The check before a mission runs: driver_check.pl.

check_mission(Module, Problems) :-
    strata_driver_check:check_mission(Module, Problems).

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
    (   setup_call_cleanup(
            asserta(active(Module), Ref),
            ( rearm, Module:mission, ! ),
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
    (   catch(call(Wrapped), E, ( phase_raised(Phase, E), throw(E) ))
    *-> phase_exit(Module, Phase, Exit),
        '$strata_phase'(end(Exit), Phase)
    ;   '$strata_phase'(end(failed), Phase),
        fail
    ).

% An error leaving a phase ends it as failed (the rules may catch the error
% and go on). What ends the mission ends the phase with it: the host closes
% it as cancelled.
phase_raised(Phase, E) :-
    (   ( E == '$aborted' ; stops_the_mission(E) )
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


                 /*******************************
                 *          THE SANDBOX         *
                 *******************************/

% A mission's rules are code someone else wrote. They are loaded with
% load_files/2's sandboxed(true): SWI-Prolog checks every directive with
% library(sandbox) before it runs it (safe_goal/1: the directive's whole
% call graph must reach only whitelisted predicates), and calls no
% expansion hook of theirs. The clauses themselves are checked after the
% load (driver_check.pl, sandbox_problems/2), before anything runs them.
% What library(sandbox) allows is pure Prolog, arithmetic, atoms and
% strings, assert/retract in the mission's own module, format/2,3 and
% print_message/2 to the console, sleep/1. It is extended here, through its
% documented hooks, with what a mission needs:

% The vehicle primitives (the catalogue's predicates defined in the
% mission's module call these).
:- multifile sandbox:safe_primitive/1,
             sandbox:safe_directive/1.
sandbox:safe_primitive(strata_driver:call_primitive(_, _, _)).
sandbox:safe_primitive(strata_driver:call_report(_, _)).
sandbox:safe_primitive(strata_driver:call_ood(_, _, _, _)).
% Console output (standard output is the operator's console).
sandbox:safe_primitive(write(_)).
sandbox:safe_primitive(writeq(_)).
sandbox:safe_primitive(nl).
sandbox:safe_primitive(system:write(_)).
sandbox:safe_primitive(system:writeq(_)).
sandbox:safe_primitive(system:print(_)).
sandbox:safe_primitive(system:nl).

% format/3 to the console streams (library(sandbox) allows format/3 only
% into text: atom(A), string(S), ...). Its ~@ and ~p calls are checked as
% library(sandbox) checks format/2's.
:- multifile sandbox:safe_meta/2.
sandbox:safe_meta(system:format(Out, Format, Args), Calls) :-
    atom(Out),
    memberchk(Out, [user_output, user_error]),
    sandbox:format_calls(Format, Args, Calls).

%   Directives: library(sandbox) asks safe_directive/1 first. It succeeds
%   for a directive Strata allows, throws error(strata_refused(Culprit, Text), _) for
%   one it refuses, and fails to leave the rest to library(sandbox).
sandbox:safe_directive(Q:Directive) :-
    prolog_load_context(module, M),
    loading(M),
    (   Q == M
    ->  mission_directive(M, Directive)
    ;   mission_directive(M, Q:Directive)
    ).

%!  allowed_library(?Name)
%
%   The libraries a mission may load (use_module/1,2, ensure_loaded/1).
allowed_library(lists).
allowed_library(apply).
allowed_library(aggregate).
allowed_library(assoc).

mission_directive(_, Var) :-
    var(Var), !, fail.
mission_directive(M, Q:Directive) :-
    Q == system, !,
    mission_directive(M, Directive).
mission_directive(M, use_module(Spec)) :- !, library_directive(M, Spec).
mission_directive(M, use_module(Spec, _)) :- !, library_directive(M, Spec).
mission_directive(M, ensure_loaded(Spec)) :- !, library_directive(M, Spec).
mission_directive(M, load_files(Spec, _)) :- !, library_directive(M, Spec).
mission_directive(M, consult(Spec)) :- !, consult_directive(M, Spec).
mission_directive(M, include(Spec)) :- !, consult_directive(M, Spec).
mission_directive(M, [H|T]) :- !, consult_directive(M, [H|T]).
mission_directive(_, set_prolog_flag(Flag, _)) :- !,
    refuse(set_prolog_flag/2, "set_prolog_flag/2: a mission cannot change Prolog's flags (`~w`)", [Flag]).
mission_directive(_, halt) :- !,
    refuse(halt/0, "halt/0: the rules called halt while loading", []).
mission_directive(_, halt(_)) :- !,
    refuse(halt/1, "halt/1: the rules called halt while loading", []).
mission_directive(M, initialization(Goal)) :- !,
    safe_goal(M:Goal).
mission_directive(M, initialization(Goal, now)) :- !,
    safe_goal(M:Goal).

library_directive(M, Spec) :-
    (   Spec = library(Name), atom(Name)
    ->  (   allowed_library(Name)
        ->  true
        ;   findall(L, allowed_library(L), Ls),
            atomic_list_concat(Ls, ', ', Allowed),
            refuse(library(Name), "library(~w) is not allowed in a mission (allowed: ~w)", [Name, Allowed])
        )
    ;   consult_directive(M, Spec)
    ).

% consult/1 of the mission's own files: a .pl file in the folder of the
% mission's file or in a folder beside it (sonar_search.pl consults
% ../tank/phases). The file is itself loaded sandboxed.
consult_directive(_, []) :- !.
consult_directive(M, [H|T]) :- !,
    consult_directive(M, H),
    consult_directive(M, T).
consult_directive(M, Spec) :-
    (   ( atom(Spec) ; string(Spec) )
    ->  true
    ;   refuse(consult/1, "consult/1 of `~q`: a mission loads its own files by name", [Spec])
    ),
    (   prolog_load_context(directory, Dir) -> true ; mission_root(M, Dir) ),
    (   absolute_file_name(Spec, Abs, [ file_type(prolog), relative_to(Dir),
                                        access(read), file_errors(fail) ])
    ->  (   mission_file(M, Abs)          % first: a file outside is not even scanned
        ->  true
        ;   refuse(consult/1, "consult/1 of `~w`: a mission loads only .pl files in its folder \c
                               or a folder beside it", [Abs])
        ),
        (   scan_problem(Abs, Line, Column, Why)
        ->  (   Line > 0
            ->  refuse(consult/1, "consult/1 of `~w`: ~w:~w: ~w", [Abs, Line, Column, Why])
            ;   refuse(consult/1, "consult/1 of `~w`: ~w", [Abs, Why])
            )
        ;   true
        )
    ;   true                    % not there: consult/1 says so, with the place
    ).

refuse(Culprit, Format, Args) :-
    format(string(Text), Format, Args),
    throw(error(strata_refused(Culprit, Text), _)).

%!  refusal(+Error, -Culprit, -Text) is semidet.
%
%   Error is the sandbox refusing a goal or a directive: Culprit is what it
%   refused (a name to find in the source), Text says so.
refusal(error(strata_refused(Culprit, Text), _), Culprit, Text) :- !.
refusal(error(permission_error(call, sandboxed, Goal0), Context), Name, Text) :- !,
    outermost_refused(Goal0, Context, Goal),
    strip_module(Goal, _, G),
    functor(G, Name, Arity),
    refused_text(Name/Arity, Text).
refusal(error(permission_error(Action, Type, (:- D)), _), Name, Text) :-
    memberchk(Type, [sandboxed_directive, sandboxed]),
    atom(Action),
    !,
    strip_module(D, _, G),
    (   callable(G) -> functor(G, Name, Arity) ; Name = D, Arity = 0 ),
    refused_text(Name/Arity, Text).
refusal(error(instantiation_error, sandbox(_, _)), call, Text) :-
    Text = "a call the sandbox cannot see through (the goal is a variable, as in call(G)): a mission's calls must be written out".

% shell/1 is refused as shell/2, which it calls: name the one the rules
% wrote, the outermost system or library predicate among the parents.
outermost_refused(Goal0, Context, Goal) :-
    (   nonvar(Context),
        Context = sandbox(_, Parents),
        is_list(Parents),
        reverse(Parents, Outermost),
        member(P, Outermost),
        nonvar(P),
        strip_module(P, PM, PG),
        callable(PG),
        (   predicate_property(PM:PG, built_in)
        ;   predicate_property(PM:PG, imported_from(_))
        )
    ->  Goal = P
    ;   Goal = Goal0
    ).

refused_text(PI, Text) :-
    format(string(Text), "~w is not allowed in a mission: the rules run in a sandbox \c
                          (no files, shells, processes, sockets, flags or foreign code; \c
                          docs/prolog.md, section 7)", [PI]).

% The place of what the sandbox refused: the first line, from the clause's
% or directive's own, that names it, and its column there.
culprit_place(File, Line, Column, Culprit, File, CLine, CColumn) :-
    (   culprit_name(Culprit, Name),
        File \== '', Line > 0,
        name_in_file(File, Line, Name, CLine, CColumn)
    ->  true
    ;   CLine = Line,
        CColumn = Column
    ).

culprit_name(Name/_, Name) :- !, atom(Name).
culprit_name(library(Name), Name) :- !, atom(Name).
culprit_name(Name, Name) :- atom(Name).

name_in_file(File, From, Name, Line, Column) :-
    catch(read_file_to_string(File, Text, []), _, fail),
    split_string(Text, "\n", "", Lines),
    nth1(Line, Lines, LineText),
    Line >= From,
    sub_string(LineText, Before, _, _, Name),
    !,
    Column is Before + 1.

% SWI calls expansion hooks while it loads sandboxed; the rules' own
% (term_expansion/2 in the mission's module) would run their code at load:
% refused, at the term they would expand.
:- multifile prolog:sandbox_allowed_expansion/1.
prolog:sandbox_allowed_expansion(M:Goal) :-
    loading(M),
    functor(Goal, Name, Arity),
    refuse(Name/Arity, "~w/~d: a mission's rules cannot expand terms or goals while they load",
           [Name, Arity]).

% Expansion in a sandboxed load: SWI-Prolog 9.0.4 aborts the process
% (pl-comp.c:4417, assertion source_line_no != -1) when it compiles a clause
% after an expansion hook was refused while expanding it, which happens for
% a body with a system:Goal call (library(sandbox) refuses the goal
% expansion it runs), or for any term once the rules define
% term_expansion/2. So the mission's terms are expanded here first
% (expand_mission_term/2, declared safe for library(sandbox)):
%  - the rules cannot define term_expansion/2,4 or goal_expansion/2,4: the
%    clause is dropped, with a located error;
%  - system:G in a clause is G: the same predicate, unless the mission's
%    module redefines it, and the only ones it does are halt/0,1, which
%    throw strata_halt as a mission's system:halt does.

% term_expansion/4, not /2: in a sandboxed load SWI-Prolog 9.0.4 loses the
% layout of what a term_expansion/2 hook returns (expand.pl binds it to the
% output), and compiling a clause without a line aborts the process as
% above. The expansion keeps the term's span (From-To), without the
% layout of its parts, which no longer match.
expand_mission_term(Term, Pos, Expanded, ExpandedPos) :-
    expand_mission_term(Term, Expanded),
    (   compound(Pos), arg(1, Pos, From), arg(2, Pos, To), integer(From), integer(To)
    ->  ExpandedPos = From-To
    ;   ExpandedPos = Pos
    ).

expand_mission_term(Term, Expanded) :-
    prolog_load_context(module, M),
    loading(M),
    nonvar(Term),
    (   Term \= (:- _),
        clause_head_of(Term, Head),
        callable(Head),
        functor(Head, Name, Arity),
        expansion_hook(Name/Arity)
    ->  format(string(Text), "~w/~d: a mission's rules cannot expand terms or goals while they load",
               [Name, Arity]),
        print_message(error, error(strata_refused(Name/Arity, Text), _)),
        Expanded = []
    ;   contains_system_call(Term),
        without_system(Term, Expanded)
    ).

clause_head_of((Head :- _), Head) :- !.
clause_head_of((Head --> _), Head) :- !.
clause_head_of(Head, Head).

expansion_hook(term_expansion/2).
expansion_hook(term_expansion/4).
expansion_hook(goal_expansion/2).
expansion_hook(goal_expansion/4).

contains_system_call(Term) :-
    sub_term(Sub, Term),
    nonvar(Sub),
    Sub = (Q:_),
    Q == system,
    !.

without_system(T, T) :- var(T), !.
without_system(Q:G, G1) :- Q == system, !, without_system(G, G1).
without_system(T, T) :- \+ compound(T), !.
without_system(T, T1) :-
    compound_name_arguments(T, N, Args),
    maplist(without_system, Args, Args1),
    compound_name_arguments(T1, N, Args1).

% Last: the hook is live from here on (the driver's own terms are not expanded).
:- multifile user:term_expansion/4.
user:term_expansion(Term, Pos, Expanded, ExpandedPos) :-
    strata_driver:expand_mission_term(Term, Pos, Expanded, ExpandedPos).
sandbox:safe_primitive(strata_driver:expand_mission_term(_, _, _, _)).
