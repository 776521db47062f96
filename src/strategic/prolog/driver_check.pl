/*  The check of a PROLOG mission before it runs (docs/prolog.md §4), part
    of the driver (driver.pl), compiled into the strata binary beside it.

    Walks every clause of the mission's module (prolog_walk_code/1) for
    calls to predicates nobody defines (a primitive the catalogue does not
    have, a known primitive with the wrong arity, a misspelt helper) and
    ood('Name', ...) calls whose Name is not an OOD primitive; each problem
    with the file and the line of the call.
*/
:- module(strata_driver_check,
          [ check_mission/2          % +Module, -Problems
          ]).
:- use_module(library(lists)).
:- use_module(library(aggregate)).
:- use_module(library(readutil)).
:- use_module(library(prolog_codewalk)).

% Reading a term from text made at run time: SWI-Prolog 9.0.4's reader can
% read freed memory on a digit followed by a quote (0'c, 16'FF) at some
% lengths of the text (fuzz/known/swi_9_0_4_reader_use_after_free.pl;
% term_to_atom/2 reached it at 504 characters). A rules file is scanned for
% that before it is read (prolog_mission.cpp, scan_rules_text); text a mission
% builds cannot be, so the predicates that parse text as a term are refused
% (docs/prolog.md, section 7). library(sandbox) lists them as safe and asks
% safe_primitive/1 before any other hook: these clauses come before its
% own, as this file loads first (ensure_driver, prolog_mission.cpp), and the
% directive at the end of this file checks that they do.
:- multifile sandbox:safe_primitive/1.
sandbox:safe_primitive(system:term_to_atom(_, _)) :- parses_text(term_to_atom/2).
sandbox:safe_primitive(system:atom_to_term(_, _, _)) :- parses_text(atom_to_term/3).
sandbox:safe_primitive(system:term_string(_, _)) :- parses_text(term_string/2).
sandbox:safe_primitive('$syspreds':term_string(_, _, _)) :- parses_text(term_string/3).

parses_text(PI) :-
    format(string(Text), "~w is not allowed in a mission: it parses text as a term, and \c
                          SWI-Prolog 9.0.4's reader has a memory bug on some texts \c
                          (docs/prolog.md, section 7); build the term instead", [PI]),
    throw(error(strata_refused(PI, Text), _)).

:- use_module(library(sandbox)).

:- dynamic walk_problem/4.           % File, Line, Callee, Text

%!  check_mission(+Module, -Problems) is det.
%
%   Problems is a list of problem(File, Line, Text): calls to predicates
%   nobody defines (a primitive the catalogue does not have among them),
%   calls the sandbox refuses (sandbox_problems/2), and a missing
%   mission/0. The line of a refused call carries its column too, as
%   problem(File, Line:Column, Text).

check_mission(Module, Problems) :-
    % A walk without the source is cheap; only when it finds a problem is
    % the source read again, for the line of each call.
    walk_mission(Module, false),
    (   walk_problem(_, _, _, _)
    ->  walk_mission(Module, true)
    ;   true
    ),
    findall(problem(F, L, T), walk_problem(F, L, _, T), Walked),
    sandbox_problems(Module, Refused),
    append(Walked, Refused, All),
    sort(All, Sorted),
    (   current_predicate(Module:mission/0)
    ->  Problems = Sorted
    ;   Problems = [problem('', 0, "no mission/0 to run: the rules must define `mission :- ...`")
                   |Sorted]
    ).

% One walk finds both the calls nobody defines and the ood/N calls (the
% arity of the OOD primitives; each extra arity costs a walk of its own).
walk_mission(Module, Source) :-
    retractall(walk_problem(_, _, _, _)),
    findall(Arity, strata_driver:ood_names(Module, Arity, _), Arities),
    (   Arities = [First|Others]
    ->  functor(Head, ood, First),
        Trace = [trace_reference(Module:Head)]
    ;   Others = [],
        Trace = []
    ),
    prolog_walk_code([ module(Module),
                       undefined(trace),
                       on_trace(strata_driver_check:walked_call(Module)),
                       source(Source)
                     | Trace ]),
    forall(member(Arity, Others),
           ( functor(OtherHead, ood, Arity),
             prolog_walk_code([ module(Module),
                                trace_reference(Module:OtherHead),
                                on_trace(strata_driver_check:ood_call(Module)),
                                source(Source)
                              ]) )).

walked_call(Module, Callee, Caller, Location) :-
    strip_module(Callee, _, Goal),
    (   functor(Goal, ood, Arity),
        strata_driver:ood_names(Module, Arity, _)
    ->  ood_call(Module, Callee, Caller, Location)
    ;   undefined_call(Module, Callee, Caller, Location)
    ).

% ood('Name', ..., X) with a Name the catalogue has no OOD primitive for.
ood_call(Module, Callee, _Caller, Location) :-
    strip_module(Callee, _, Goal),
    functor(Goal, ood, Arity),
    arg(1, Goal, Name),
    atom(Name),
    strata_driver:ood_names(Module, Arity, Names),
    \+ memberchk(Name, Names),
    !,
    location_file_line(Location, File, Line),
    format(string(Text), "ood('~w', ...): `~w` is not an ood primitive in the catalogue \c
                          (`strata primitives` lists them)", [Name, Name]),
    (   walk_problem(File, Line, ood(Name), _)
    ->  true
    ;   assertz(walk_problem(File, Line, ood(Name), Text))
    ).
ood_call(_, _, _, _).

undefined_call(Module, Callee, _Caller, Location) :-
    strip_module(Callee, _, Goal),
    functor(Goal, Name, Arity),
    location_file_line(Location, File, Line),
    undefined_text(Module, Name, Arity, Text),
    (   walk_problem(File, Line, Name/Arity, _)
    ->  true
    ;   assertz(walk_problem(File, Line, Name/Arity, Text))
    ).

location_file_line(clause_term_position(Ref, Pos), File, Line) :- !,
    clause_file_line(Ref, File, ClauseLine),
    (   compound(Pos), arg(1, Pos, From), integer(From), File \== '',
        catch(offset_line(File, From, GoalLine), _, fail)
    ->  Line = GoalLine                 % the line of the call itself
    ;   Line = ClauseLine
    ).
location_file_line(clause(Ref), File, Line) :- !,
    clause_file_line(Ref, File, Line).
location_file_line(file(File, Line, _, _), File, Line) :- !.
location_file_line(_, '', 0).

offset_line(File, Offset, Line) :-
    read_file_to_codes(File, Codes, []),
    length(Prefix, Offset),
    append(Prefix, _, Codes),
    !,
    aggregate_all(count, member(0'\n, Prefix), Newlines),
    Line is Newlines + 1.

clause_file_line(Ref, File, Line) :-
    (   clause_property(Ref, file(File)) -> true ; File = '' ),
    (   clause_property(Ref, line_count(Line)) -> true ; Line = 0 ).

undefined_text(Module, Name, Arity, Text) :-
    primitive_prefix(Name, Kind, Primitive),
    !,
    (   known_arities(Module, Name, Arities)
    ->  format(string(Text), "~w/~d: ~w takes ~w argument(s) here: use ~w",
               [Name, Arity, Primitive, Arity, Arities])
    ;   format(string(Text), "~w/~d: `~w` is not an ~w primitive in the catalogue \c
                              (`strata primitives` lists them)",
               [Name, Arity, Primitive, Kind])
    ).
undefined_text(_, Name, Arity, Text) :-
    format(string(Text), "~w/~d is called but not defined", [Name, Arity]).

primitive_prefix(Name, exec, Primitive) :-
    atom_concat(exec_, Primitive, Name), !.
primitive_prefix(Name, ask, Primitive) :-
    atom_concat(ask_, Primitive, Name), !.

known_arities(Module, Name, Arities) :-
    findall(Text, ( current_predicate(Module:Name/A),
                    format(atom(Text), '~w/~d', [Name, A]) ), Arities0),
    Arities0 \== [],
    atomic_list_concat(Arities0, ' or ', Arities).


%!  sandbox_problems(+Module, -Problems) is det.
%
%   Every clause of the mission's own predicates must pass
%   library(sandbox)'s safe_goal/1 (with the driver's extensions,
%   driver.pl): a clause whose body can reach a predicate outside the
%   sandbox is a problem(File, Line:Column, Text) at the call. A call
%   reached through a helper of the rules is reported at the helper's own
%   clause; calls nobody defines are the walk's to report.
%
%   Rules that pass are the common case: every clause's body is checked at
%   once, as one conjunction (a conjunction is safe when each of its goals
%   is, and one safe_goal/1 call verifies each predicate it reaches once,
%   where a call per clause verified the primitives again for each: the tank
%   mission's check went from 3.5 ms to 1.5 ms). Only when that raises is
%   each clause checked alone, to place every problem.

sandbox_problems(Module, Problems) :-
    findall(Body, checked_clause(Module, Body, _), Bodies),
    (   conjunction(Bodies, All),
        catch(safe_goal(Module:All), _, fail)
    ->  Problems = []
    ;   findall(Problem, sandbox_problem(Module, Problem), Problems0),
        sort(Problems0, Problems)
    ).

conjunction([], true).
conjunction([Goal|Goals], (Goal, Rest)) :-
    conjunction(Goals, Rest).

% A clause of the rules' own predicates (not the primitives the driver
% defines from the catalogue, nor what the module imports).
checked_clause(Module, Body, Ref) :-
    current_predicate(Module:Name/Arity),
    functor(Head, Name, Arity),
    \+ predicate_property(Module:Head, imported_from(_)),
    \+ strata_driver:reserved(Module, Name/Arity),
    clause(Module:Head, Body, Ref).

sandbox_problem(Module, problem(File, Line:Column, Text)) :-
    checked_clause(Module, Body, Ref),
    catch(safe_goal(Module:Body), E, true),
    nonvar(E),
    \+ E = error(existence_error(procedure, _), _),
    \+ reached_through_helper(Module, E),
    (   strata_driver:refusal(E, Culprit, Text)
    ->  true
    ;   Culprit = none,
        message_to_codes(E, Text)
    ),
    clause_file_line(Ref, File0, Line0),
    (   File0 \== '' -> File = File0 ; File = '' ),
    strata_driver:culprit_place(File0, Line0, 0, Culprit, _, Line, Column).

% The refused goal was reached through another of the rules' predicates:
% that predicate's clause is reported itself.
reached_through_helper(Module, error(_, sandbox(_, Parents))) :-
    is_list(Parents),
    member(P, Parents),
    nonvar(P),
    strip_module(P, PM, PG),
    PM == Module,
    callable(PG),
    \+ predicate_property(Module:PG, imported_from(_)),
    \+ predicate_property(Module:PG, built_in),
    !.

message_to_codes(E, Text) :-
    catch(message_to_codes_(E, Text), _, format(string(Text), "~q", [E])).
message_to_codes_(E, Text) :-
    message_to_string(E, Text0),
    normalize_space(string(Text), Text0).

% The refusals above hold only if they come before library(sandbox)'s own
% clauses: a driver where they do not is not loaded at all.
:- (   catch(( safe_goal(user:term_to_atom(_, _)), Refused = false ),
             error(strata_refused(term_to_atom/2, _), _),
             Refused = true),
       Refused == true
   ->  true
   ;   throw(error(strata_driver_broken("library(sandbox) was loaded before the driver's \c
                                         refusal of the predicates that parse text"), _))
   ).
