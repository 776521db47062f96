// The driver's foreign predicates ('$strata_call'/3, '$strata_report'/2,
// '$strata_phase'/2, '$strata_guards_open'/2, '$strata_guards_close'/2,
// '$strata_scan'/2, '$strata_library'/1, '$strata_real_path'/2): where the
// rules reach the host that runs them (docs/prolog.md).
#include <cstdlib>
#include <filesystem>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "coral/loader.h"
#include "core/file.h"
#include "strategic/prolog_driver.h"
#include "strategic/prolog_rules_scan.h"

namespace strata::strategic::prolog_detail {
namespace {

// The executor whose query is running; set by PrologMissionQuery::next().
PrologHost* g_host = nullptr;
// LoadLimits::max_bytes of the load under way, for '$strata_scan'/2.
std::size_t g_max_rules_bytes = LoadLimits{}.max_bytes;

// A primitive argument: a number, or text (an atom or a string). Raises a
// Prolog error and returns nullopt otherwise.
std::optional<tactical::Value> value_of(term_t t) {
  double number = 0;
  if (PL_is_number(t) && PL_get_float(t, &number)) return tactical::Value::of(number);
  if (auto text = prolog::get_text(t, CVT_ATOM | CVT_STRING)) return tactical::Value::of(*std::move(text));
  if (PL_is_variable(t)) {
    PL_instantiation_error(t);
  } else {
    PL_type_error("number_or_text", t);
  }
  return std::nullopt;
}

bool call_arguments(term_t name_t, term_t list, std::string& name, std::vector<tactical::Value>& args) {
  char* s = nullptr;
  if (!PL_get_atom_chars(name_t, &s)) return PL_type_error("atom", name_t);
  name = s;
  term_t head = PL_new_term_ref();
  term_t tail = PL_copy_term_ref(list);
  while (PL_get_list(tail, head, tail)) {
    auto v = value_of(head);
    if (!v) return false;
    args.push_back(std::move(*v));
  }
  if (!PL_get_nil(tail)) return PL_type_error("list", list);
  return true;
}

bool no_host() {
  term_t ex = PL_new_term_ref();
  return PL_unify_term(ex, PL_FUNCTOR_CHARS, "strata_error", 1, PL_CHARS,
                       "a primitive was called outside a running mission") &&
         PL_raise_exception(ex);
}

// Raises strata_guard_trip(Scope, Guard).
bool raise_trip(const GuardTripSignal& trip) {
  term_t ex = PL_new_term_ref();
  return PL_unify_term(ex, PL_FUNCTOR_CHARS, "strata_guard_trip", 2, PL_INT64, static_cast<int64_t>(trip.scope),
                       PL_UTF8_CHARS, trip.guard.c_str()) &&
         PL_raise_exception(ex);
}

// A call made while a trip is pending is not made: the trip is raised again
// (docs/prolog.md §8: a cleanup or a catch-all cannot reach the vehicle).
// True when it was refused so (the caller returns FALSE).
bool refuse_during_trip(term_t name_t) {
  auto trip = g_host->pending_trip();
  if (!trip) return false;
  g_host->call_not_made(prolog::text_of(name_t));
  (void)raise_trip(*trip);
  return true;
}

// '$strata_call'(+Name, +Args, -Answer): yields to the host until the
// vehicle answers, then unifies Answer with 1 or 0.
foreign_t pl_strata_call(term_t name_t, term_t args_t, term_t answer_t, control_t handle) {
  alignas(8) static int token = 0;
  switch (PL_foreign_control(handle)) {
    case PL_FIRST_CALL: {
      if (!g_host) return no_host();
      if (refuse_during_trip(name_t)) return FALSE;
      std::string name;
      std::vector<tactical::Value> args;
      if (!call_arguments(name_t, args_t, name, args)) return FALSE;
      g_host->primitive(name, std::move(args));
      PL_yield_address(&token);
    }
    case PL_RESUME: {
      if (g_host) {
        if (auto trip = g_host->pending_trip()) return raise_trip(*trip);
      }
      auto answer = g_host ? g_host->answer() : std::nullopt;
      if (!answer) {
        term_t ex = PL_new_term_ref();
        PL_put_atom_chars(ex, "strata_cancelled");
        return PL_raise_exception(ex);
      }
      return PL_unify_integer(answer_t, *answer);
    }
    default: return TRUE;
  }
}

foreign_t pl_strata_report(term_t name_t, term_t args_t) {
  if (!g_host) return no_host();
  if (refuse_during_trip(name_t)) return FALSE;
  std::string name;
  std::vector<tactical::Value> args;
  if (!call_arguments(name_t, args_t, name, args)) return FALSE;
  g_host->report(name, std::move(args));
  return TRUE;
}

// '$strata_phase'(+Event, +Phase): Event is start or end(Exit).
foreign_t pl_strata_phase(term_t event_t, term_t phase_t) {
  if (!g_host) return TRUE;  // the rules run outside a mission (plunit)
  std::string phase = prolog::text_of(phase_t);
  char* s = nullptr;
  if (PL_get_atom_chars(event_t, &s)) {
    g_host->phase_started(phase);
    return TRUE;
  }
  term_t exit = PL_new_term_ref();
  if (PL_is_functor(event_t, PL_new_functor(PL_new_atom("end"), 1)) && PL_get_arg(1, event_t, exit)) {
    g_host->phase_ended(phase, prolog::text_of(exit));
    return TRUE;
  }
  return PL_domain_error("phase_event", event_t);
}

// One term of a guard's condition: t(Ask, Args, Negated).
bool guard_term(term_t t, GuardTerm& term) {
  if (!PL_is_functor(t, PL_new_functor(PL_new_atom("t"), 3))) return PL_domain_error("guard_term", t);
  term_t name_t = PL_new_term_ref();
  term_t args_t = PL_new_term_ref();
  term_t negated_t = PL_new_term_ref();
  if (!PL_get_arg(1, t, name_t) || !PL_get_arg(2, t, args_t) || !PL_get_arg(3, t, negated_t)) return FALSE;
  if (!call_arguments(name_t, args_t, term.ask, term.args)) return FALSE;
  term.negated = prolog::text_of(negated_t) == "true";
  term.text = term.negated ? "not " + term.ask : term.ask;
  for (std::size_t i = 0; i < term.args.size(); ++i) {
    term.text += (i == 0 ? "(" : ", ") + tactical::to_string(term.args[i]);
  }
  if (!term.args.empty()) term.text += ")";
  return TRUE;
}

// '$strata_guards_open'(+Specs, -Scope): Specs is a list of
// spec(Name, Period, Terms), Terms a list of t(Ask, Args, Negated).
foreign_t pl_strata_guards_open(term_t specs_t, term_t scope_t) {
  if (!g_host) return no_host();
  std::vector<GuardSpec> guards;
  term_t head = PL_new_term_ref();
  term_t tail = PL_copy_term_ref(specs_t);
  term_t arg = PL_new_term_ref();
  while (PL_get_list(tail, head, tail)) {
    GuardSpec g;
    if (!PL_is_functor(head, PL_new_functor(PL_new_atom("spec"), 3))) return PL_domain_error("guard_spec", head);
    if (!PL_get_arg(1, head, arg)) return FALSE;
    g.name = prolog::text_of(arg);
    if (!PL_get_arg(2, head, arg) || !PL_get_float(arg, &g.period_s)) return PL_type_error("number", arg);
    if (!PL_get_arg(3, head, arg)) return FALSE;
    term_t term_head = PL_new_term_ref();
    term_t term_tail = PL_copy_term_ref(arg);
    while (PL_get_list(term_tail, term_head, term_tail)) {
      GuardTerm term;
      if (!guard_term(term_head, term)) return FALSE;
      g.terms.push_back(std::move(term));
    }
    if (g.terms.empty()) return PL_domain_error("guard_condition", arg);
    guards.push_back(std::move(g));
  }
  return PL_unify_int64(scope_t, static_cast<int64_t>(g_host->open_guards(guards)));
}

// '$strata_guards_close'(+Scope, -Trip): Trip is none, or tripped(Guard).
foreign_t pl_strata_guards_close(term_t scope_t, term_t trip_t) {
  int64_t scope = 0;
  if (!PL_get_int64(scope_t, &scope)) return PL_type_error("integer", scope_t);
  if (!g_host) return PL_unify_atom_chars(trip_t, "none");
  auto tripped = g_host->close_guards(static_cast<std::uint64_t>(scope));
  if (!tripped) return PL_unify_atom_chars(trip_t, "none");
  return PL_unify_term(trip_t, PL_FUNCTOR_CHARS, "tripped", 1, PL_UTF8_CHARS, tripped->c_str());
}

// '$strata_scan'(+File, -Problem): Problem is ok, or problem(Line, Column,
// Text) for what the reader must not see (scan_rules_text()). A file that
// cannot be read is ok here: loading it says so.
foreign_t pl_strata_scan(term_t file_t, term_t problem_t) {
  char* file = nullptr;
  if (!PL_get_file_name(file_t, &file, 0)) return FALSE;
  auto read = core::read_regular_file(file, g_max_rules_bytes);
  if (!read && read.error().code == core::ErrorCode::Overflow) {
    return PL_unify_term(
        problem_t, PL_FUNCTOR_CHARS, "problem", 3, PL_INT64, int64_t{0}, PL_INT64, int64_t{0}, PL_UTF8_STRING,
        fmt::format("the file is over the limit of {} bytes for rules (--max-rules-size)", g_max_rules_bytes).c_str());
  }
  std::error_code ec;
  if (!read && std::filesystem::exists(file, ec) && !std::filesystem::is_regular_file(file, ec)) {
    return PL_unify_term(problem_t, PL_FUNCTOR_CHARS, "problem", 3, PL_INT64, int64_t{0}, PL_INT64, int64_t{0},
                         PL_UTF8_STRING, "not a regular file (a FIFO or a device is never read)");
  }
  if (!read) return PL_unify_atom_chars(problem_t, "ok");
  const auto found = scan_rules_text(read.value());
  if (!found) return PL_unify_atom_chars(problem_t, "ok");
  return PL_unify_term(problem_t, PL_FUNCTOR_CHARS, "problem", 3, PL_INT64, static_cast<int64_t>(found->line), PL_INT64,
                       static_cast<int64_t>(found->column), PL_UTF8_STRING, found->text.c_str());
}

// '$strata_library'(-Dirs): the folders `:- use_phase(Name).` looks in for
// Name.pl, in order (docs/library.md), as a list of atoms.
foreign_t pl_strata_library(term_t dirs_t) {
  term_t list = PL_new_term_ref();
  PL_put_nil(list);
  const std::vector<std::string> dirs = coral::library_dirs("prolog");
  for (auto it = dirs.rbegin(); it != dirs.rend(); ++it) {
    term_t head = PL_new_term_ref();
    if (!PL_put_chars(head, PL_ATOM | REP_UTF8, it->size(), it->c_str()) || !PL_cons_list(list, head, list)) {
      return FALSE;
    }
  }
  return PL_unify(dirs_t, list);
}

// '$strata_real_path'(+Path, -Real): Path with every symbolic link and
// `.`/`..` resolved (realpath(3)); fails when Path does not exist. The
// check of which files a mission may load compares real paths, so a link
// in the mission's folder to a file elsewhere is outside it.
foreign_t pl_strata_real_path(term_t path_t, term_t real_t) {
  char* path = nullptr;
  if (!PL_get_chars(path_t, &path, CVT_ATOM | CVT_STRING | REP_UTF8 | CVT_EXCEPTION)) return FALSE;
  const std::unique_ptr<char, decltype(&std::free)> real(::realpath(path, nullptr), &std::free);
  if (!real) return FALSE;
  return PL_unify_chars(real_t, PL_ATOM | REP_UTF8, static_cast<std::size_t>(-1), real.get());
}

}  // namespace

void set_running_host(PrologHost* host) { g_host = host; }

void set_max_rules_bytes(std::size_t max_bytes) { g_max_rules_bytes = max_bytes; }

void register_foreign_predicates() {
  PL_register_foreign_in_module("strata_driver", "$strata_call", 3, reinterpret_cast<pl_function_t>(pl_strata_call),
                                PL_FA_NONDETERMINISTIC);
  PL_register_foreign_in_module("strata_driver", "$strata_report", 2, reinterpret_cast<pl_function_t>(pl_strata_report),
                                0);
  PL_register_foreign_in_module("strata_driver", "$strata_scan", 2, reinterpret_cast<pl_function_t>(pl_strata_scan), 0);
  PL_register_foreign_in_module("strata_driver", "$strata_library", 1,
                                reinterpret_cast<pl_function_t>(pl_strata_library), 0);
  PL_register_foreign_in_module("strata_driver", "$strata_real_path", 2,
                                reinterpret_cast<pl_function_t>(pl_strata_real_path), 0);
  PL_register_foreign_in_module("strata_driver", "$strata_phase", 2, reinterpret_cast<pl_function_t>(pl_strata_phase),
                                0);
  PL_register_foreign_in_module("strata_driver", "$strata_guards_open", 2,
                                reinterpret_cast<pl_function_t>(pl_strata_guards_open), 0);
  PL_register_foreign_in_module("strata_driver", "$strata_guards_close", 2,
                                reinterpret_cast<pl_function_t>(pl_strata_guards_close), 0);
}

}  // namespace strata::strategic::prolog_detail
