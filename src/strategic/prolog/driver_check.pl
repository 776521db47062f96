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
:- use_module(library(occurs)).

% Reading a term from text made at run time: SWI-Prolog 9.0.4's reader can
% read freed memory on a digit followed by a quote (0'c, 16'FF) at some
% lengths of the text (fuzz/known/swi_9_0_4_reader_use_after_free.pl;
% term_to_atom/2 reached it at 504 characters). A rules file is scanned for
% that before it is read (prolog_mission.cpp, scan_rules_text); text a mission
% builds cannot be, so the predicates that parse text as a term are refused
% (docs/prolog.md, section 7). library(sandbox) lists them as safe and asks
% safe_primitive/1 before any other hook: that predicate is wrapped here,
% so the refusal comes before every clause of it, whichever file loaded
% first (ensure_driver, prolog_driver.cpp, loads library(sandbox) before
% this file); the directive at the end of this file checks that it does.
:- use_module(library(prolog_wrap)).
:- wrap_predicate(sandbox:safe_primitive(Goal), strata_parses_text, Safe,
                  (   strata_driver_check:parsing_primitive(Goal, PI)
                  ->  strata_driver_check:parses_text(PI)
                  ;   Safe
                  )).

parsing_primitive(system:term_to_atom(_, _), term_to_atom/2).
parsing_primitive(system:atom_to_term(_, _, _), atom_to_term/3).
parsing_primitive(system:term_string(_, _), term_string/2).
parsing_primitive('$syspreds':term_string(_, _, _), term_string/3).

parses_text(PI) :-
    format(string(Text), "~w is not allowed in a mission: it parses text as a term, and \c
                          SWI-Prolog 9.0.4's reader has a memory bug on some texts \c
                          (docs/prolog.md, section 7); build the term instead", [PI]),
    throw(error(strata_refused(PI, Text), _)).

:- use_module(library(sandbox)).

:- dynamic walk_problem/4.           % File, Line, Callee, Text
:- dynamic passed_check/2.           % Hash, Rules: rules the walk and the sandbox found nothing in

%!  check_mission(+Module, -Problems) is det.
%
%   Problems is a list of problem(File, Line, Text): calls to predicates
%   nobody defines (a primitive the catalogue does not have among them),
%   calls the sandbox refuses (sandbox_problems/2), guards that are not
%   what docs/prolog.md §8 says (guard_problems/2), and a missing
%   mission/0. The line of a refused call carries its column too, as
%   problem(File, Line:Column, Text).

check_mission(Module, Problems) :-
    % The first check of a process keeps nothing: most processes (`strata
    % check`, `strata run`) check one mission once, and the snapshot costs
    % about an eighth of a check.
    flag(strata_checks, Checks, Checks + 1),
    (   Checks > 0,
        rules_snapshot(Module, Rules, Hash)
    ->  true
    ;   Hash = none
    ),
    (   Hash \== none,
        passed_check(Hash, Passed),
        Passed =@= Rules
    ->  Walked = [],
        Refused = []
    ;   walk_problems(Module, Walked),
        sandbox_problems(Module, Refused),
        (   Walked == [], Refused == [], Hash \== none
        ->  remember_passed(Hash, Rules)
        ;   true
        )
    ),
    guard_problems(Module, Guards),
    append([Walked, Refused, Guards], All),
    sort(All, Sorted),
    (   current_predicate(Module:mission/0)
    ->  Problems = Sorted
    ;   Problems = [problem('', 0, "no mission/0 to run: the rules must define `mission :- ...`")
                   |Sorted]
    ).

walk_problems(Module, Walked) :-
    % A walk without the source is cheap; only when it finds a problem is
    % the source read again, for the line of each call.
    walk_mission(Module, false),
    (   walk_problem(_, _, _, _)
    ->  walk_mission(Module, true)
    ;   true
    ),
    findall(problem(F, L, T), walk_problem(F, L, _, T), Walked).

%!  rules_snapshot(+Module, -Rules, -Hash) is semidet.
%
%   Rules is all that the walk and the sandbox's check of Module see:
%   every predicate of the module (sorted by name and arity), with where
%   it is imported from, or with its properties and its clauses, the
%   primitives the driver defined from the catalogue among them. Hash is
%   its variant_sha1/2. Rules that passed both once pass them again, in
%   any module: check_mission/2 keeps the last few (passed_check/2) and
%   does not walk or check rules equal (=@=) to one of them, which saves
%   most of a load when one process loads the same rules run after run
%   (bench/prolog_bench, a campaign's worker that cannot keep them, the
%   studio), from its second check on. Only rules that passed are kept: a
%   problem is always found again, with its place. Fails, and nothing is
%   kept, when the rules name their own module (the same text in another
%   module means something else) or cannot be hashed.

rules_snapshot(Module, Rules, Hash) :-
    findall(PI-What, module_predicate(Module, PI, What), Rules0),
    msort(Rules0, Rules),
    \+ ( sub_term(Sub, Rules), Sub == Module ),
    catch(variant_sha1(Rules, Hash), _, fail).

module_predicate(Module, Name/Arity, What) :-
    current_predicate(Module:Name/Arity),
    functor(Head, Name, Arity),
    (   predicate_property(Module:Head, imported_from(From))
    ->  What = imported(From)
    ;   findall(P, snapshot_property(Module:Head, P), Properties),
        findall((Head :- Body), clause(Module:Head, Body), Clauses),
        What = own(Properties, Clauses)
    ).

snapshot_property(Goal, Property) :-
    member(Property, [ dynamic, multifile, discontiguous, tabled, thread_local,
                       transparent, meta_predicate(_), foreign, public, non_terminal ]),
    predicate_property(Goal, Property).

% The last 16 rules that passed, newest last; rules of more than about
% 2 MB of terms are not kept (16 of them would hold too much).
remember_passed(Hash, Rules) :-
    (   passed_check(Hash, Known), Known =@= Rules
    ->  true
    ;   term_size(Rules, Cells),
        Cells > 250000
    ->  true
    ;   assertz(passed_check(Hash, Rules)),
        aggregate_all(count, passed_check(_, _), Count),
        (   Count > 16
        ->  once(retract(passed_check(_, _)))
        ;   true
        )
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

%!  guard_problems(+Module, -Problems) is det.
%
%   The rules' guards (docs/prolog.md §8): guard(Name, Period, Condition,
%   Handler) and phase_guard(Phase, Name, Period, Condition, Handler), each
%   a fact (not dynamic); Name an atom, unique in its scope; Period a number
%   of seconds from 0.1 to 3600; Condition a non-empty list of terms, each
%   an ASK primitive of the catalogue Q or not(Q), with literal arguments;
%   Handler a goal of a predicate the rules define (or a primitive). Each
%   problem at the line of its fact.

guard_problems(Module, Problems) :-
    findall(P, guard_problem(Module, P), Problems).

guard_problem(Module, Problem) :-
    member(PI, [guard/4, phase_guard/5]),
    current_predicate(Module:PI),
    PI = Name/Arity,
    functor(Head, Name, Arity),
    \+ predicate_property(Module:Head, imported_from(_)),
    (   predicate_property(Module:Head, dynamic)
    ->  first_clause_place(Module:Head, File, Line),
        format(string(Text), "~w must not be dynamic: the guards are the facts the rules load \c
                              (a guard asserted while they run is never polled)", [PI]),
        Problem = problem(File, Line, Text)
    ;   PI == phase_guard/5,
        \+ current_predicate(Module:execute_phase/1)
    ->  first_clause_place(Module:Head, File, Line),
        Problem = problem(File, Line, "phase_guard/5 guards phases, which are execute_phase/1 calls: \c
                                       the rules define no execute_phase/1")
    ;   clause(Module:Head, Body, Ref),
        clause_file_line(Ref, File, Line),
        guard_fact_problem(Module, PI, Head, Body, Ref, Text),
        Problem = problem(File, Line, Text)
    ).

first_clause_place(Head, File, Line) :-
    (   clause(Head, _, Ref)
    ->  clause_file_line(Ref, File, Line)
    ;   File = '', Line = 0
    ).

guard_fact_problem(_, PI, _, Body, _, Text) :-
    Body \== true,
    !,
    format(string(Text), "~w must be a fact: a guard is declared, not computed", [PI]).
guard_fact_problem(Module, PI, Head, _, Ref, Text) :-
    guard_fields(PI, Head, Scope, Name, Period, Condition, Handler),
    (   \+ atom(Name)
    ->  format(string(Text), "~w: the guard's name must be an atom, not ~q", [PI, Name])
    ;   duplicate_guard(Module, PI, Scope, Name, Ref)
    ->  format(string(Text), "~w: a guard named ~q is declared twice for the same scope", [PI, Name])
    ;   \+ ( number(Period), Period >= 0.1, Period =< 3600 )
    ->  format(string(Text), "guard ~w: the period is ~q: it must be a number of seconds \c
                              from 0.1 to 3600", [Name, Period])
    ;   condition_problem(Module, Condition, Problem)
    ->  format(string(Text), "guard ~w: ~w", [Name, Problem])
    ;   handler_problem(Module, Handler, Problem)
    ->  format(string(Text), "guard ~w: ~w", [Name, Problem])
    ).

guard_fields(guard/4, guard(N, P, C, H), mission, N, P, C, H).
guard_fields(phase_guard/5, phase_guard(S, N, P, C, H), S, N, P, C, H).

% Reported at the second declaration.
duplicate_guard(Module, F/A, Scope, Name, Ref) :-
    functor(Head, F, A),
    findall(R, nth_clause(Module:Head, _, R), Refs),
    append(Before, [Ref|_], Refs),
    !,
    member(R0, Before),
    functor(Other, F, A),
    clause(Module:Other, _, R0),
    guard_fields(F/A, Other, OtherScope, OtherName, _, _, _),
    OtherName == Name,
    OtherScope =@= Scope,
    !.

condition_problem(_, Condition, "the condition must be a non-empty list of ASK primitives, \c
                                 each q or not(q): [system_problem, not(gps_available)]") :-
    \+ ( is_list(Condition), Condition \== [] ),
    !.
condition_problem(Module, Condition, Problem) :-
    member(Term, Condition),
    term_problem(Module, Term, Problem),
    !.

term_problem(_, Term, "a term of the condition is unbound") :-
    var(Term), !.
term_problem(Module, not(Q), Problem) :- !,
    (   var(Q) -> Problem = "a term of the condition is unbound"
    ;   term_problem(Module, Q, Problem)
    ).
term_problem(_, Q, Problem) :-
    \+ callable(Q), !,
    format(string(Problem), "~q is not an ASK primitive", [Q]).
term_problem(Module, Q, Problem) :-
    Q =.. [Ask|Args],
    length(Args, N),
    atom_concat(ask_, Ask, F),
    A is N + 1,
    (   strata_driver:primitive_predicate(Module, F/A)
    ->  (   member(Arg, Args), \+ atomic(Arg)
        ->  format(string(Problem), "~q: a guard asks with literal arguments (numbers or text), \c
                                     not ~q", [Q, Arg])
        ;   fail
        )
    ;   known_arities(Module, F, _)
    ->  findall(K, ( strata_driver:primitive_predicate(Module, F/KA), K is KA - 1 ), Ks),
        atomic_list_concat(Ks, ' or ', KsText),
        format(string(Problem), "~w takes ~w argument(s), not ~d", [Ask, KsText, N])
    ;   format(string(Problem), "`~w` is not an ask primitive in the catalogue \c
                                 (`strata primitives` lists them)", [Ask])
    ).

handler_problem(_, Handler, "the handler must be a goal, not a variable") :-
    var(Handler), !.
handler_problem(_, Handler, Problem) :-
    \+ callable(Handler), !,
    format(string(Problem), "the handler ~q is not a goal", [Handler]).
handler_problem(Module, Handler, Problem) :-
    strip_module(Module:Handler, M, Goal),
    functor(Goal, F, A),
    (   M \== Module
    ->  format(string(Problem), "the handler ~q must be a predicate of the rules, not of another module", [Handler])
    ;   current_predicate(Module:F/A),
        \+ predicate_property(Module:Goal, imported_from(_))
    ->  fail
    ;   format(string(Problem), "the handler ~w/~d is not defined: it must be a predicate the rules \c
                                 define (or a primitive)", [F, A])
    ).

% The refusals above hold only if they come before library(sandbox)'s own
% clauses (the wrapper above): a driver where they do not is not loaded at all.
:- (   catch(( safe_goal(user:term_to_atom(_, _)), Refused = false ),
             error(strata_refused(term_to_atom/2, _), _),
             Refused = true),
       Refused == true
   ->  true
   ;   throw(error(strata_driver_broken("library(sandbox) was loaded before the driver's \c
                                         refusal of the predicates that parse text"), _))
   ).
