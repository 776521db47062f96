#pragma once
// Reaction time (docs/verification.md, "Reaction time"): how long, at worst
// and at best, from an event of a mission's run (a fault starting, a guard
// tripping, a phase starting) to a call of a primitive, an exit of the
// mission, or the vehicle at the surface.
//
// The model is a time Petri net built from the compiled program: the
// mission's analysis net (coral/analysis.h) with every PHASE call replaced
// by a copy of its phase's analysis net (parameters bound to the call's
// arguments), so nested phases and their guards run beside each other as
// in the engine. The mission's own transitions, a guard's drops and a
// phase's end take no time; a call in flight is answered within an interval
// from the catalogue: [0, reply_s] for an exec, ask or ood, and
// [N, N + reply_s] for one that waits for its argument N first (sleep).
// Time is explored in ticks of 0.1 s (the vehicle's control cycle), with
// the intervals rounded outward to whole ticks; for closed intervals with
// bounds on whole ticks this discrete-time exploration gives the same
// worst and best cases as dense time.
//
// A fault `fault Q` (Q an ask) starts at any moment of the run; before it
// every ask of Q answers 0 and from it every one answers 1 (a latched
// fault); the other asks answer either way. The worst case is the longest
// time from the event to the first TO after it over every run; "unbounded"
// when a cycle that lets time pass can repeat without TO (the cycle is
// given). Runs that end after the event without TO are reported apart.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"
#include "coral/program.h"
#include "coral/trace_step.h"

namespace strata::coral {

// What the timing analysis needs of a vehicle primitive (from the catalogue).
struct PrimitiveTiming {
  double reply_s = 0;  // the vehicle answers within this (after wait_arg's value)
  // The argument, in seconds, the vehicle waits for before it answers
  // (sleep's), by index; nullopt: none.
  std::optional<std::size_t> wait_arg;
  double wait_arg_max = 0;  // its largest value, when a call's is not known
};

// The most `require`s a mission may state (BadRequirement past it): each is
// a timing analysis of the whole mission at every verification.
inline constexpr std::size_t kMaxRequirements = 16;

struct BoundQuery {
  enum class From { Fault, Trip, Start };
  enum class To { Call, Exit, Surface };
  From from = From::Fault;
  std::string from_name;    // the ask (Fault), the guard (Trip), the phase (Start)
  bool fault_value = true;  // Fault: the answer from the fault on (`fault not Q`: 0)
  To to = To::Call;
  std::optional<ast::TacticType> to_verb;  // Call: exec, ask or ood; nullopt: any
  std::string to_name;                     // Call: the primitive; Exit: the mission's exit
  std::optional<double> within_s;          // `... within S`: the requirement
  std::string text;                        // as written
};

// "fault system_problem -> exec surface", "trip leak -> surface within 30",
// "start leg -> exit closed". Errors say the column (1-based) first:
// "column 7: ...".
core::Result<BoundQuery> parse_bound(std::string_view text);

struct BoundOptions {
  std::function<std::optional<PrimitiveTiming>(std::string_view)> primitive;
  double tick_s = 0.1;
  // To::Surface: from `exec surface` to the vehicle at the surface, at most.
  double ascent_s = 0;
  std::size_t max_states = 4'000'000;
};

struct BoundStep {
  std::optional<double> t_s;  // since the event (nullopt: before it)
  std::string net;            // the instance: "survey", "survey/leg#2"
  std::string what;           // "fires check_depth: ASK depth_reached", "answer 1", "3.0 s pass"
  // The same step in the verifier's terms, with its instance, net and time
  // (the studio plays it on the nets as it plays a counterexample).
  TraceStep trace;
};

struct BoundAnswer {
  enum class Verdict { Bounded, Unbounded, NoEvent, Unsupported };
  Verdict verdict = Verdict::Unsupported;
  double worst_s = 0;
  double best_s = 0;
  std::vector<BoundStep> path;   // Bounded: to the worst case; Unbounded: to the cycle
  std::vector<BoundStep> cycle;  // Unbounded: the steps that can repeat for ever
  bool ends_without = false;     // a run can end after the event without TO
  std::vector<BoundStep> ends_without_path;
  std::size_t states = 0;
  std::string message;  // NoEvent, Unsupported: why
};

BoundAnswer analyse_bound(const Program& program, const BoundQuery& query, const BoundOptions& options);

std::string_view bound_verdict_name(BoundAnswer::Verdict v);

}  // namespace strata::coral
