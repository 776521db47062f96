// The PROLOG driver (prolog/driver.pl with driver_load.pl and
// driver_sandbox.pl, prolog/driver_check.pl and prolog/driver_keep.pl, the
// libraries of prolog/driver_libraries.pl, compiled in): loading it once
// into the engine, precompiled or from its text, and calling its predicates.
#include <iostream>
#include <string>
#include <string_view>

#include <fmt/format.h>

#include "strategic/prolog_driver.h"
#include "strategic/prolog_driver_check_text.h"
#include "strategic/prolog_driver_keep_text.h"
#include "strategic/prolog_driver_libraries_text.h"
#include "strategic/prolog_driver_load_text.h"
#include "strategic/prolog_driver_precompiled.h"
#include "strategic/prolog_driver_sandbox_text.h"
#include "strategic/prolog_driver_text.h"

namespace strata::strategic::prolog_detail {

term_t new_atom(const std::string& name) {
  term_t t = PL_new_term_ref();
  PL_put_atom_chars(t, name.c_str());
  return t;
}

namespace {

// Module:Name(Args...)
term_t module_goal(const char* module, const char* name, std::initializer_list<term_t> args) {
  term_t refs = PL_new_term_refs(static_cast<int>(args.size()));
  int i = 0;
  for (term_t a : args) {
    if (!PL_put_term(refs + i++, a)) PL_clear_exception();
  }
  term_t goal = PL_new_term_ref();
  term_t call = PL_new_term_ref();
  if (!PL_cons_functor_v(goal, PL_new_functor(PL_new_atom(name), args.size()), refs) ||
      !PL_cons_functor(call, PL_new_functor(PL_new_atom(":"), 2), new_atom(module), goal)) {
    PL_clear_exception();
  }
  return call;
}

}  // namespace

term_t driver_goal(const char* name, std::initializer_list<term_t> args) {
  return module_goal("strata_driver", name, args);
}

core::Result<bool> call_driver(const char* name, std::initializer_list<term_t> args) {
  return prolog::call_term(driver_goal(name, args));
}

core::Result<bool> call_driver_keep(const char* name, std::initializer_list<term_t> args) {
  return prolog::call_term(module_goal("strata_driver_keep", name, args));
}

namespace {

// Loads one of the driver's files from its text: a module file (into
// "user", which it leaves for its own module), or a part of a module (its
// clauses go into `into`).
core::Result<void> load_module_text(const char* name, std::string_view text, const char* into = "user") {
  prolog::Frame frame;
  auto goal = prolog::parse_term(
      "open_string(Text, S), call_cleanup(load_files(Into:Name, [stream(S), silent(true), imports([])]), close(S))");
  if (!goal) return goal.error();
  term_t open = PL_new_term_ref();
  term_t text_t = PL_new_term_ref();
  term_t load = PL_new_term_ref();
  term_t call_load = PL_new_term_ref();
  term_t file_t = PL_new_term_ref();
  term_t into_t = PL_new_term_ref();
  term_t name_t = PL_new_term_ref();
  if (!PL_get_arg(1, goal.value(), open) || !PL_get_arg(1, open, text_t) ||
      !PL_unify_chars(text_t, PL_STRING, text.size(), text.data()) || !PL_get_arg(2, goal.value(), load) ||
      !PL_get_arg(1, load, call_load) || !PL_get_arg(1, call_load, file_t) || !PL_get_arg(1, file_t, into_t) ||
      !PL_get_arg(2, file_t, name_t) || !PL_unify_atom_chars(into_t, into) || !PL_unify_atom_chars(name_t, name)) {
    return core::make_error(core::ErrorCode::Internal, "cannot build the driver's load goal");
  }
  auto r = prolog::call_term(goal.value());
  if (!r || !r.value()) {
    return core::make_error(core::ErrorCode::Internal, fmt::format("the PROLOG driver ({}) did not load: {}", name,
                                                                   r ? std::string("failed") : r.error().message));
  }
  return {};
}

// The driver from its text: the libraries it uses first, in the order of
// driver_libraries.pl and importing nothing (as precompile_driver.pl
// compiles them), then its files.
core::Result<void> load_driver_text() {
  if (auto r = load_module_text("strata_driver_libraries", kDriverLibrariesText); !r) return r;
  auto libraries = prolog::call_once(
      "forall(strata_driver_libraries:driver_library(Spec),"
      " load_files(user:Spec, [if(not_loaded), silent(true), imports([])]))");
  if (!libraries || !libraries.value()) {
    return core::make_error(core::ErrorCode::Internal,
                            fmt::format("the PROLOG driver's libraries did not load: {}",
                                        libraries ? std::string("failed") : libraries.error().message));
  }
  if (auto r = load_module_text("strata_driver_check", kDriverCheckText); !r) return r;
  if (auto r = load_module_text("strata_driver", kDriverText); !r) return r;
  if (auto r = load_module_text("strata_driver_load", kDriverLoadText, "strata_driver"); !r) return r;
  if (auto r = load_module_text("strata_driver_sandbox", kDriverSandboxText, "strata_driver"); !r) return r;
  return load_module_text("strata_driver_keep", kDriverKeepText);
}

}  // namespace

core::Result<void> ensure_driver() {
  static bool loaded = false;
  // Also once loaded: from a thread other than SWI-Prolog's it is an error.
  if (auto r = prolog::initialise(); !r) return r.error();
  if (loaded) return {};
  PrecompiledDriver precompiled = load_precompiled_driver();
  if (!precompiled.loaded) {
    if (!precompiled.note.empty()) {
      std::cerr << "strata: note: the precompiled PROLOG driver " << precompiled.note
                << "; loading the driver from its text instead (a slower start)\n";
    }
    if (auto r = load_driver_text(); !r) return r;
  }
  register_foreign_predicates();
  if (auto set = prolog::call_once("assertz(strata_driver:uncatchable_stops)"); !set || !set.value()) {
    return core::make_error(core::ErrorCode::Internal, "cannot set up the PROLOG driver");
  }
  loaded = true;
  return {};
}

}  // namespace strata::strategic::prolog_detail
