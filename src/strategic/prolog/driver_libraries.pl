/*  The SWI-Prolog libraries the PROLOG driver uses (docs/prolog.md §6),
    part of the driver, compiled into the strata binary beside it.

    ensure_driver (prolog_driver.cpp) loads each of them, in this order and
    importing nothing, before the driver's own files, whether the driver
    comes from the precompiled file or from its text: so both ways load the
    same code in the same order. precompile_driver.pl puts each into the
    precompiled file as a part of its own, which only works for a library
    whose own libraries come before it: the order is dependencies first
    (the libraries the driver's files name, those these load or autoload
    as they load, and the three the first check of a mission autoloads:
    nb_set, option, prolog_metainference). A library missing here is still
    loaded, by the file that names it, but from source at every start.
*/
:- module(strata_driver_libraries,
          [ driver_library/1            % ?Spec
          ]).

driver_library(library(predicate_options)).
driver_library(library(dialect/swi/syspred_options)).
driver_library(library(shlib)).
driver_library(library(readutil)).
driver_library(library(error)).
driver_library(library(lists)).
driver_library(library(aggregate)).
driver_library(library(debug)).
driver_library(library(record)).
driver_library(library(prolog_codewalk)).
driver_library(library(apply)).
driver_library(library(apply_macros)).
driver_library(library(assoc)).
driver_library(library(prolog_format)).
driver_library(library(sandbox)).
driver_library(library(solution_sequences)).
driver_library(library(prolog_wrap)).
driver_library(library(occurs)).
driver_library(library(nb_set)).
driver_library(library(option)).
driver_library(library(prolog_metainference)).
