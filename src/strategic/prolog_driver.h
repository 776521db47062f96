#pragma once
// Internal to strata_strategic: the PROLOG mission driver's parts below
// PrologMission and PrologMissionQuery (prolog_mission.h). prolog_driver.cpp loads the
// driver's modules and calls their predicates; prolog_foreign.cpp holds the
// foreign predicates the driver calls back into, and who they serve.
// Threads: the Prolog engine's thread only.
#include <cstddef>
#include <initializer_list>
#include <string>

#include "core/result.h"
#include "prolog/engine.h"
#include "strategic/prolog_mission.h"

namespace strata::strategic::prolog_detail {

// A fresh term holding the atom `name`.
term_t new_atom(const std::string& name);
// strata_driver:Name(Args...)
term_t driver_goal(const char* name, std::initializer_list<term_t> args);
core::Result<bool> call_driver(const char* name, std::initializer_list<term_t> args);
// strata_driver_keep:Name(Args...) (prolog/driver_keep.pl)
core::Result<bool> call_driver_keep(const char* name, std::initializer_list<term_t> args);
// Starts the engine and loads the driver once per process (its foreign
// predicates too); later calls return at once, on the engine's thread, and
// with an error on any other (prolog::initialise()).
core::Result<void> ensure_driver();

// Registers the foreign predicates in module strata_driver (ensure_driver()).
void register_foreign_predicates();
// The host whose query is running ('$strata_call'/3 and the others reach it),
// or nullptr between queries.
void set_running_host(PrologHost* host);
// The size limit '$strata_scan'/2 reads rule files with (the load's).
void set_max_rules_bytes(std::size_t max_bytes);

}  // namespace strata::strategic::prolog_detail
