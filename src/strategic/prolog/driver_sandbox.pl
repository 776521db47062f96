/*  The sandbox a mission's rules load and run in: part of the PROLOG
    driver (driver.pl), loaded into its module, strata_driver, last;
    compiled into the strata binary beside it. library(sandbox) extended
    with what a mission needs and refusing the rest with a located reason:
    the vehicle primitives and console output allowed, the directives and
    libraries a mission may use, and the expansion of the mission's terms.
*/
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
% A directive that does more than declare predicates or load files may do
% something else at a second load of the same files (ask the time, draw a
% random number): it is noted, and rules whose load ran one are loaded
% again for every run outside a campaign, never taken back in place of a
% load (KeepRules::Reproducible, driver_keep.pl). The clause below decides.
sandbox:safe_directive(_:Directive) :-
    prolog_load_context(module, M),
    loading(M),
    \+ declaring_directive(Directive),
    note_load_effect(M, Directive),
    fail.
sandbox:safe_directive(Q:Directive) :-
    prolog_load_context(module, M),
    loading(M),
    (   Q == M
    ->  mission_directive(M, Directive)
    ;   mission_directive(M, Q:Directive)
    ).

% `:- if(G).` and `:- elif(G).` run G as the file loads, and SWI-Prolog
% 9.0.4 runs it without asking library(sandbox): its conditional
% compilation ('$eval_if'/1, expand.pl) acts before any hook sees the term,
% and is not a directive. G is checked here as a directive's goal is; a
% refused G is an error at its line (the load prints what '$eval_if'/1
% raises) and the condition is false.
:- wrap_predicate('$expand':'$eval_if'(G), strata_if, If,
                  (   prolog_load_context(module, M),
                      strata_driver:loading(M)
                  ->  safe_goal(M:G),
                      strata_driver:note_load_effect(M, if(G)),
                      If
                  ;   If
                  )).

declaring_directive(D) :-
    var(D), !, fail.
declaring_directive(_:D) :- !,
    declaring_directive(D).
declaring_directive(dynamic(_)).
declaring_directive(discontiguous(_)).
declaring_directive(multifile(_)).
declaring_directive(consult(_)).
declaring_directive(ensure_loaded(_)).
declaring_directive(use_module(_)).
declaring_directive(use_module(_, _)).
declaring_directive([_|_]).

note_load_effect(M, Directive) :-
    (   load_effect(M, _)
    ->  true
    ;   assertz(load_effect(M, Directive))
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
mission_directive(M, use_module(Spec)) :- !, library_directive(M, use_module/1, Spec).
mission_directive(M, use_module(Spec, _)) :- !, library_directive(M, use_module/2, Spec).
mission_directive(M, ensure_loaded(Spec)) :- !, library_directive(M, ensure_loaded/1, Spec).
mission_directive(M, load_files(Spec, Options)) :- !, library_directive(M, load_files(Options), Spec).
mission_directive(M, consult(Spec)) :- !, consult_directive(M, consult/1, Spec).
mission_directive(M, include(Spec)) :- !, include_directive(M, Spec).
mission_directive(M, [H|T]) :- !, consult_directive(M, consult/1, [H|T]).
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

library_directive(M, How, Spec) :-
    (   Spec = library(Name), atom(Name)
    ->  (   allowed_library(Name)
        ->  true
        ;   findall(L, allowed_library(L), Ls),
            atomic_list_concat(Ls, ', ', Allowed),
            refuse(library(Name), "library(~w) is not allowed in a mission (allowed: ~w)", [Name, Allowed])
        )
    ;   consult_directive(M, How, Spec)
    ).

% SWI-Prolog asks about an include/1 twice: as it reads the term (a valid
% one is read in place and never run), then, when that refused it, as a
% directive to run ('$execute_directive_3'/1). Run as a goal, include/1
% does nothing (it is no predicate: "Unknown procedure"), so that asking
% is always refused: silently when the reading refused the same include
% just before (the message hook drops strata_refused_again, driver_load.pl),
% so a refusal is said once, at its place; with its own reason otherwise
% (an include qualified by a module is never read in place).
include_directive(M, Spec) :-
    (   running_a_directive
    ->  (   clause(include_refused(M, Refused), true, Ref),
            Refused =@= Spec
        ->  erase(Ref),
            throw(error(strata_refused_again, _))
        ;   refuse(include/1, "include/1 of `~q` run as a goal: write it as a directive of its own, \c
                               `:- include(File).`", [Spec])
        )
    ;   retractall(include_refused(M, _)),
        catch(consult_directive(M, include/1, Spec), E,
              ( assertz(include_refused(M, Spec)), throw(E) ))
    ).

% Whether the nearest of the two askings' callers is the one that runs a
% directive (a file consulted by a directive is read under that one).
running_a_directive :-
    prolog_current_frame(Frame),
    nearest_asking(Frame, system:'$execute_directive_3'/1).

nearest_asking(Frame, Asking) :-
    prolog_frame_attribute(Frame, parent, Parent),
    (   prolog_frame_attribute(Parent, predicate_indicator, PI),
        memberchk(PI, [system:'$execute_directive_3'/1, system:'$expanded_term'/10])
    ->  PI == Asking
    ;   nearest_asking(Parent, Asking)
    ).

% consult/1 of the mission's own files: a .pl file in the folder of the
% mission's file or in a folder beside it (sonar_search.pl consults
% ../tank/phases). The file is itself loaded sandboxed. How is the
% directive's name and arity, or load_files(Options).
consult_directive(_, _, []) :- !.
consult_directive(M, How, [H|T]) :- !,
    consult_directive(M, How, H),
    consult_directive(M, How, T).
consult_directive(M, How, Spec) :-
    (   How = load_files(_) -> PI = load_files/2 ; PI = How ),
    (   ( atom(Spec) ; string(Spec) )
    ->  true
    ;   refuse(PI, "~w of `~q`: a mission loads its own files by name", [PI, Spec])
    ),
    (   prolog_load_context(directory, Dir) -> true ; mission_root(M, Dir) ),
    (   absolute_file_name(Spec, Abs, [ file_type(prolog), relative_to(Dir),
                                        access(read), file_errors(fail) ])
    ->  (   mission_file(M, Abs)          % first: a file outside is not even scanned
        ->  true
        ;   real_path(Abs, Real),
            Real \== Abs
        ->  refuse(PI, "~w of `~w`: a link to `~w`; a mission loads only .pl files in its \c
                         folder or a folder beside it, links resolved", [PI, Abs, Real])
        ;   refuse(PI, "~w of `~w`: a mission loads only .pl files in its folder \c
                         or a folder beside it", [PI, Abs])
        ),
        (   \+ once_only(How),           % those are skipped (driver_load.pl)
            loading_cycle(M, Abs, Path)
        ->  refuse(PI, "~w of `~w`: a loop: that file is being loaded already (~w); \c
                         a file cannot load itself, directly or through others", [PI, Abs, Path])
        ;   true
        ),
        (   scan_problem(Abs, Line, Column, Why)
        ->  (   Line > 0
            ->  refuse(PI, "~w of `~w`: ~w:~w: ~w", [PI, Abs, Line, Column, Why])
            ;   refuse(PI, "~w of `~w`: ~w", [PI, Abs, Why])
            )
        ;   true
        )
    ;   true                    % not there: consult/1 says so, with the place
    ).

% Loads a file only when it is not loaded yet: a file being loaded is
% skipped, as in SWI-Prolog, rather than refused as a loop.
once_only(ensure_loaded/1).
once_only(use_module/_).
once_only(load_files(Options)) :-
    is_list(Options),
    memberchk(if(How), Options),
    How \== true.

%!  loading_cycle(+Module, +File, -Path) is semidet.
%
%   File is open in the load that reached this directive: the file the
%   directive is in, or one that consulted or included it on the way here.
%   Loading it again would start over for ever (SWI-Prolog 9.0.4 does not
%   stop it: a file that includes itself ran into the load's time limit).
%   Path is the chain of mission files and lines that leads back to it,
%   outermost first (`a.pl:2 -> b.pl:1 -> a.pl`).
loading_cycle(M, File, Path) :-
    prolog_load_context(file, Current),
    '$input_context'(Context),
    % Cheap first: the path below resolves every file on the way (realpath),
    % which a chain of 300 includes paid at each of its directives (2 s).
    (   File == Current
    ->  true
    ;   memberchk(input(_, File, _, _), Context)
    ),
    source_location(_, Line),
    findall(F-L, ( member(input(_, F, L, _), Context), atom(F), mission_file(M, F) ), Inner),
    reverse(Inner, Outer),
    append(Outer, [Current-Line], Open),
    memberchk(File-_, Open),
    findall(Step, ( member(F-L, Open), file_base_name(F, B), format(atom(Step), "~w:~w", [B, L]) ), Steps),
    file_base_name(File, Base),
    append(Steps, [Base], All),
    atomic_list_concat(All, ' -> ', Path).

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
% wrote, the outermost system or library predicate among the parents. A
% meta-predicate (catch/3, findall/3, forall/2, call/N, the control
% constructs) only carries the refused goal: name the goal inside it
% (catch(abolish(f/1), _, true) is refused for abolish/1, not catch/3).
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
        ),
        \+ calls_goal(PM:PG)
    ->  Goal = P
    ;   Goal = Goal0
    ).

% A meta-predicate that calls one of its arguments as a goal (catch(0,?,0),
% findall(?,0,-)); not one that only takes a module-qualified argument
% (use_foreign_library(:)).
calls_goal(PI) :-
    predicate_property(PI, meta_predicate(Spec)),
    Spec =.. [_|Args],
    member(A, Args),
    ( integer(A) ; A == (^) ; A == (//) ),
    !.

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
    (   subsumes_term((:- use_phase(_)), Term)
    ->  Term = (:- use_phase(Name)),
        use_phase_expansion(Name, Expanded)
    ;   Term \= (:- _),
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

% `:- use_phase(Name).`: the library's Name.pl, consulted (driver_load.pl,
% library_phase_file/2); a name the library does not have is an error at
% the directive, naming the folders looked in.
use_phase_expansion(Name, (:- consult(Abs))) :-
    library_phase_file(Name, Abs),
    !,
    prolog_load_context(module, M),
    assertz(load_resolution(M, phase(Name, Abs))).
use_phase_expansion(Name, []) :-
    library_dirs(Dirs),
    (   Dirs == [] -> Looked = 'there are none' ; atomic_list_concat(Dirs, ', ', Looked) ),
    (   library_phase_name(Name)
    ->  format(string(Text), "use_phase(~w): no library phase `~w`: ~w.pl is in none of the library's \c
                              folders (~w); STRATA_LIBRARY adds folders (docs/library.md)",
               [Name, Name, Name, Looked])
    ;   format(string(Text), "use_phase(~q): a library phase is named by a plain name, as \c
                              `:- use_phase(goto).`", [Name])
    ),
    print_message(error, error(strata_refused(use_phase/1, Text), _)).

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
