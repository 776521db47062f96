/*  Builds the precompiled PROLOG driver (docs/prolog.md §6): one quick-load
    file (.qlf) holding the libraries of driver_libraries.pl and the
    driver's own files, compiled as ensure_driver (prolog_driver.cpp) loads
    them from their text, so that strata loads them at start-up instead of
    compiling them. Run by the build (src/strategic/CMakeLists.txt) with the
    system's swipl:

        swipl -f none --no-packs -q -g strata_precompile:main -t 'halt(1)' \
              precompile_driver.pl -- SOURCE_DIR OUTPUT.qlf

    SOURCE_DIR holds driver_libraries.pl and the driver's files. It writes
    OUTPUT.pl (what is compiled: one load per part) and OUTPUT.qlf, and
    halts with 0, or 1 with the error on the first problem.

    Each part is loaded with load_files/2's qcompile(part), which puts its
    code into the .qlf; a library a part loads itself is compiled into the
    .qlf only as a load to make at start-up, so the list is in the order
    dependencies first. While this process compiles (term_expansion/2
    below), a part whose file is already loaded is left a plain load
    (SWI-Prolog 9.0.4 would record it as an empty file, which the start-up
    then refuses to load as a module), and a use_module/1,2 of a listed
    library not loaded yet is left to the wrapper (a cycle in the list). The driver's files are loaded from a string stream
    under the name ensure_driver gives them (strata_driver, ...), so the
    .qlf registers the same source names as a load from text. This process
    uses only built-in predicates before the compile: a library loaded here
    before it would be left out of the .qlf and compiled at every start.
*/
:- module(strata_precompile, [main/0]).

% Only while this process compiles: see the header. In system, not user:
% library modules do not see user's hooks.
:- multifile system:term_expansion/2.
:- dynamic system:term_expansion/2.
:- dynamic listed_library/1.            % Path: driver_libraries.pl names it
system:term_expansion((:- load_files(Spec, Options)), (:- load_files(Spec, Plain))) :-
    memberchk(qcompile(part), Options),
    loaded(Spec),
    drop_part(Options, Plain).
system:term_expansion((:- use_module(Spec)), (:- true)) :-
    listed_not_loaded(Spec).
system:term_expansion((:- use_module(Spec, _)), (:- true)) :-
    listed_not_loaded(Spec).

% A library the list names, not loaded yet: a library that loads it before
% its place in the list (predicate_options.pl loads syspred_options.pl,
% whose directives need predicate_options) leaves it to the wrapper, which
% loads it next as a part of its own; nested, it would not be one.
listed_not_loaded(Spec) :-
    file_path(Spec, Path),
    listed_library(Path),
    \+ source_file(Path).

loaded(Spec) :-
    file_path(Spec, Path),
    source_file(Path).

file_path(Spec, Path) :-
    strip_module(Spec, _, Plain),
    \+ atom(Plain),                    % the driver's streams: never files
    absolute_file_name(Plain, Path, [file_type(prolog), access(read), file_errors(fail)]).

drop_part([], []).
drop_part([qcompile(part)|T], T) :- !.
drop_part([H|T0], [H|T]) :- drop_part(T0, T).

% The driver's files: Into:Name as ensure_driver loads them, and the file.
driver_part(user, strata_driver_check, 'driver_check.pl').
driver_part(user, strata_driver, 'driver.pl').
driver_part(strata_driver, strata_driver_load, 'driver_load.pl').
driver_part(strata_driver, strata_driver_sandbox, 'driver_sandbox.pl').
driver_part(user, strata_driver_keep, 'driver_keep.pl').

main :-
    current_prolog_flag(argv, Argv),
    (   last_two(Argv, SourceDir, Qlf),
        file_name_extension(Base, qlf, Qlf)
    ->  true
    ;   throw(error(usage("precompile_driver.pl -- SOURCE_DIR OUTPUT.qlf"), _))
    ),
    file_name_extension(Base, pl, Wrapper),
    catch(build(SourceDir, Wrapper), E, (print_message(error, E), halt(1))),
    halt(0).

build(SourceDir, Wrapper) :-
    atomic_list_concat([SourceDir, '/driver_libraries.pl'], LibrariesFile),
    text_stream(LibrariesFile, strata_in_libraries, LibrariesText),
    libraries(LibrariesText, Libraries),
    forall(lib_member(Spec, Libraries),
           (   file_path(Spec, Path)
           ->  assertz(listed_library(Path))
           ;   throw(error(existence_error(library, Spec), _))
           )),
    forall(driver_part(_, Name, File),
           (   atomic_list_concat([SourceDir, '/', File], Path),
               text_stream(Path, Name, _)
           )),
    setup_call_cleanup(
        open(Wrapper, write, Out, [encoding(utf8)]),
        write_wrapper(Out, Libraries),
        close(Out)),
    nothing_loaded_yet,
    qcompile(user:Wrapper),
    % The same check as the driver's own load: the refusals of
    % driver_check.pl hold in what was compiled.
    (   current_predicate(strata_driver:open_mission/2)
    ->  true
    ;   throw(error(existence_error(procedure, strata_driver:open_mission/2), _))
    ).

last_two([A, B], A, B) :- !.
last_two([_|T], A, B) :- last_two(T, A, B).

% No file but this one is loaded (autoloading a library here would keep it
% out of the .qlf): only built-ins are used before the compile.
nothing_loaded_yet :-
    source_location_file(Self),
    (   source_file(File),
        File \== Self
    ->  throw(error(strata_precompile(loaded_before_compile(File)), _))
    ;   true
    ).

source_location_file(Self) :-
    source_file(strata_precompile:main, Self).

% A stream named Alias on the text of File (read with built-ins only).
text_stream(File, Alias, Text) :-
    setup_call_cleanup(
        open(File, read, In, [encoding(utf8)]),
        read_string(In, _, Text),
        close(In)),
    open_string(Text, S),
    set_stream(S, alias(Alias)).

% The driver_library(Spec) facts of driver_libraries.pl, in order.
libraries(Text, Libraries) :-
    setup_call_cleanup(
        open_string(Text, In),
        read_facts(In, Libraries),
        close(In)).

read_facts(In, Libraries) :-
    read_term(In, Term, []),
    (   Term == end_of_file
    ->  Libraries = []
    ;   Term = driver_library(Spec)
    ->  Libraries = [Spec|Rest],
        read_facts(In, Rest)
    ;   read_facts(In, Libraries)
    ).

% The wrapper: driver_libraries.pl, each library, then the driver's files.
write_wrapper(Out, Libraries) :-
    format(Out, "% Generated by precompile_driver.pl: compiled into the .qlf beside it.~n", []),
    Options = [silent(true), imports([]), qcompile(part)],
    directive(Out, load_files(user:strata_driver_libraries, [stream(strata_in_libraries)|Options])),
    library_directives(Libraries, Out, Options),
    forall(driver_part(Into, Name, _),
           directive(Out, load_files(Into:Name, [stream(Name)|Options]))).

lib_member(X, [X|_]).
lib_member(X, [_|T]) :- lib_member(X, T).

library_directives([], _, _).
library_directives([Spec|Specs], Out, Options) :-
    directive(Out, load_files(user:Spec, [if(not_loaded)|Options])),
    library_directives(Specs, Out, Options).

% writeq/1, not portray_clause/2: that one is a library's (listing).
directive(Out, Goal) :-
    format(Out, ":- ~q.~n", [Goal]).
