/*  Loading a mission's rules: part of the PROLOG driver (driver.pl),
    loaded into its module, strata_driver, after it; compiled into the
    strata binary beside it. load_mission/2,3 load a mission's files into the
    module driver.pl made for it, keeping what SWI-Prolog says as located
    messages; check_mission/2 checks them (driver_check.pl). The sandbox
    they load in is driver_sandbox.pl.
*/
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
    retractall(include_refused(_, _)),
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
    assertz(load_resolution(Mission, file(Spec, Dir, Abs))),
    (   memberchk(if(If), Options),             % ensure_loaded/1 of a file being loaded:
        If \== true,                            % it is, as in SWI-Prolog
        loading_cycle(Mission, Abs, _)
    ->  true
    ;   load_mission_file(Module, Abs, Options)
    ).

%!  resolves_again(+Resolution) is semidet.
%
%   A file name a load resolved (load_resolution/2) names the same file
%   today: no file has come to stand before it (a phase2.pl beside the
%   mission's file where a library phase was found, another STRATA_LIBRARY).

resolves_again(file(Spec, Dir, Abs)) :-
    absolute_file_name(Spec, Again, [ file_type(prolog), relative_to(Dir),
                                      access(read), file_errors(fail) ]),
    Again == Abs.
resolves_again(phase(Name, Abs)) :-
    library_phase_file(Name, Again),
    Again == Abs.

% Abs is one of the files a mission may load: a .pl file in the folder of
% the mission's file or in a folder beside it (consult_directive/2), or a
% phase of the library (use_phase/1). Both are compared as real paths
% (symbolic links resolved): a link in the folder to a file elsewhere is
% outside it (its text showed in the load's syntax errors), and a folder
% reached through a link is the folder it names, however the mission's
% path and the working folder spell it.
mission_file(_, Abs) :-
    library_file(Abs),
    !.
mission_file(M, Abs) :-
    file_name_extension(_, pl, Abs),
    mission_root(M, Root0),  % Root's parent holds Root, and the folders beside it
    real_path(Root0, Root),
    real_path(Abs, Real),
    file_directory_name(Root, Parent),
    Parent \== '/',
    atom_concat(Parent, '/', Under),            % not /m/tank_evil for /m/tank
    sub_atom(Real, 0, _, _, Under).

real_path(Path, Real) :-
    (   current_predicate(strata_driver:'$strata_real_path'/2)
    ->  '$strata_real_path'(Path, Real)
    ;   Real = Path             % without the host (plunit): as written
    ).

%!  library_phase_file(+Name, -Abs) is semidet.
%
%   The phase library (docs/library.md): Abs is Name.pl in the first folder
%   of the library path that has it ('$strata_library'/1: STRATA_LIBRARY's
%   folders, then Strata's own library/prolog). Name is a plain name.
%   `:- use_phase(Name).` consults it (driver_sandbox.pl), sandboxed as the
%   mission's own files are.

library_phase_file(Name, Abs) :-
    library_phase_name(Name),
    library_dirs(Dirs),
    member(Dir, Dirs),
    atomic_list_concat([Dir, /, Name, '.pl'], Path),
    absolute_file_name(Path, Abs, [access(read), file_errors(fail)]),
    exists_file(Abs),
    !.

library_phase_name(Name) :-
    atom(Name),
    Name \== '',
    atom_codes(Name, Codes),
    forall(member(C, Codes), code_type(C, csym)).

library_dirs(Dirs) :-
    (   current_predicate(strata_driver:'$strata_library'/1)
    ->  '$strata_library'(Dirs)
    ;   Dirs = []               % without the host (plunit): no library
    ).

% Abs is a phase of the library: the file use_phase/1 finds for its name.
library_file(Abs) :-
    file_name_extension(Base, pl, Abs),
    file_base_name(Base, Name),
    library_phase_name(Name),
    library_phase_file(Name, Found),
    Found == Abs.

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
user:message_hook(error(strata_refused_again, _), _, _) :-
    loading(_),
    !.                          % said once already (driver_sandbox.pl, include/1)
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
