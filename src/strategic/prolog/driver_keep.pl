/*  Rules kept loaded between runs (prolog_mission.h, KeepRules), part of
    the driver (driver.pl), compiled into the strata binary beside it.

    A campaign's worker runs one mission's rules case after case. Loading
    and checking them again for each case is most of a case's Prolog, so
    the host keeps the module of rules that loaded without errors, and
    before each later run puts back what the rules could have changed:

      - every dynamic predicate's clauses, as they were right after the
        load and the check (keep_mission/1 takes that snapshot);
      - the predicates the rules created while they ran (assertz/1 or
        retractall/1 of a predicate the files do not define) are removed.

    That is all a run can change that outlives it, as the sandbox lets the
    rules change nothing else (docs/prolog.md, section 7) but Prolog's flags
    and stack limits (set_prolog_flag/2, set_prolog_stack/2), tables, and
    what predicate_property/2 tells of a predicate's clauses (where they
    were loaded from, which a restored clause no longer says). Rules that
    reach any of those are not kept: keepable_mission/1 fails for them, and
    the host loads them afresh for each run.
*/
:- module(strata_driver_keep,
          [ keepable_mission/1,      % +Module
            reproducible_mission/1,  % +Module
            keep_mission/1,          % +Module
            restore_mission/1,       % +Module
            mission_files/2,         % +Module, -Files
            forget_kept/1            % +Module
          ]).
:- use_module(library(lists)).
:- use_module(library(occurs)).
:- use_module(library(prolog_wrap)).

:- dynamic kept_predicates/2,        % Module, PIs: its predicates right after the load
           kept_clauses/3.           % Module, PI, Clauses: a dynamic one's clauses then

%!  keepable_mission(+Module) is semidet.
%
%   True when restore_mission/1 puts back all that a run of Module's rules
%   can change: no predicate of theirs is tabled or thread-local, and no
%   clause names a predicate whose effect outlives the run, or that sees
%   the difference between loaded and restored clauses (stateful/1). The
%   sandbox lets the rules call only what their clauses write out (a goal
%   in a variable is refused), so the names in the clauses are all there
%   is to look at.

keepable_mission(Module) :-
    \+ ( mission_predicate(Module, Head),
         (   predicate_property(Module:Head, tabled)
         ;   predicate_property(Module:Head, thread_local)
         ;   \+ predicate_property(Module:Head, foreign),
             clause(Module:Head, Body),
             names_state(Body)
         )
       ).

names_state(Body) :-
    sub_term(T, Body),
    (   atom(T) -> Name = T
    ;   compound(T) -> compound_name_arity(T, Name, _)
    ),
    stateful(Name),
    !.

stateful(set_prolog_flag).
stateful(set_prolog_stack).
stateful(predicate_property).
stateful(abolish_all_tables).
stateful(abolish_table_subgoals).
stateful(abolish_module_tables).
stateful(b_setval).
stateful(nb_setval).
stateful(nb_linkval).

%!  reproducible_mission(+Module) is semidet.
%
%   True when a second load of Module's files, unchanged, would do what
%   their first did: every directive only declared predicates (dynamic/1,
%   discontiguous/1, multifile/1) or loaded files (consult/1, [File],
%   ensure_loaded/1, use_module/1,2, use_phase/1), and no :- if/elif ran a
%   goal (driver_sandbox.pl notes the others as they run). Taking back such
%   rules, put back as restore_mission/1 does, is the same as loading
%   them again; a directive that computes (get_time/1, random/1, a goal
%   that asserts) could give another answer the second time.

reproducible_mission(Module) :-
    \+ strata_driver:load_effect(Module, _).

%!  keep_mission(+Module) is det.
%
%   Takes the snapshot restore_mission/1 puts back: Module's predicates,
%   and each dynamic one's clauses.

keep_mission(Module) :-
    forget_kept(Module),
    findall(PI, mission_pi(Module, PI), PIs),
    assertz(kept_predicates(Module, PIs)),
    forall(( member(Name/Arity, PIs),
             functor(Head, Name, Arity),
             predicate_property(Module:Head, dynamic)
           ),
           ( findall((Head :- Body), clause(Module:Head, Body), Clauses),
             assertz(kept_clauses(Module, Name/Arity, Clauses))
           )).

%!  restore_mission(+Module) is semidet.
%
%   Puts Module back as keep_mission/1 found it: the dynamic predicates
%   created since are abolished, and each dynamic predicate whose clauses changed
%   gets those of the snapshot again, in their order. Fails when Module was
%   not kept, or when a file name its load resolved now names another file
%   (driver_load.pl, resolves_again/1): it must be loaded again.

restore_mission(Module) :-
    kept_predicates(Module, PIs),
    forall(strata_driver:load_resolution(Module, Resolution),
           strata_driver:resolves_again(Resolution)),
    % Only dynamic ones: what assertz/1 and retractall/1 made. The one
    % wrap_predicate/4 adds for execute_phase/1 ('$wrap$execute_phase'/1,
    % dynamic too) stays: the wrapper calls it.
    forall(( mission_pi(Module, PI), \+ memberchk(PI, PIs),
             PI = Name/Arity, functor(Head, Name, Arity),
             predicate_property(Module:Head, dynamic),
             \+ wrapper_closure(Module, Name, Arity)
           ),
           abolish(Module:PI)),
    forall(kept_clauses(Module, PI, Clauses),
           restore_clauses(Module, PI, Clauses)).

wrapper_closure(Module, Name, Arity) :-
    atom_concat('$wrap$', Wrapped, Name),
    functor(Head, Wrapped, Arity),
    current_predicate_wrapper(Module:Head, _, _, _),
    !.

restore_clauses(Module, Name/Arity, Clauses) :-
    functor(Head, Name, Arity),
    findall((Head :- Body), clause(Module:Head, Body), Now),
    (   Now =@= Clauses
    ->  true
    ;   retractall(Module:Head),
        forall(member(Clause, Clauses), assertz(Module:Clause))
    ).

%!  mission_files(+Module, -Files) is det.
%
%   The files loaded into Module: the mission's own file, those it
%   consulted and those any of them included (:- include/1, at any depth),
%   whose content the host checks before it takes the kept module back.

mission_files(Module, Files) :-
    findall(File, source_file_property(File, load_context(Module, _, _)), Loaded),
    included_files(Loaded, Loaded, Files0),
    sort(Files0, Files).

included_files([], Seen, Seen).
included_files([File|Files], Seen, All) :-
    findall(Inc, ( source_file_property(File, includes(Inc, _)),
                   \+ memberchk(Inc, Seen) ), Incs0),
    sort(Incs0, Incs),
    append(Seen, Incs, Seen1),
    append(Files, Incs, Next),
    included_files(Next, Seen1, All).

%!  forget_kept(+Module) is det.

forget_kept(Module) :-
    retractall(kept_predicates(Module, _)),
    retractall(kept_clauses(Module, _, _)).

% Module's own predicates (not those it imports).
mission_pi(Module, Name/Arity) :-
    current_predicate(Module:Name/Arity),
    functor(Head, Name, Arity),
    \+ predicate_property(Module:Head, imported_from(_)).

mission_predicate(Module, Head) :-
    mission_pi(Module, Name/Arity),
    functor(Head, Name, Arity).
