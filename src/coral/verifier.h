#pragma once
// Verification of a compiled mission before it runs (docs/verification.md):
// for each net of the program, its analysis net (analysis.h) is explored
// whole (petri/reach_graph.h) and these properties are decided:
//
//   bounded          no place can grow without limit
//   one_safe         no reachable marking puts 2 tokens in a place
//   no_dead          every mission transition can fire in some run
//   no_deadlock      nothing stops outside the exits (nothing enabled,
//                    nothing in flight, no exit marked)
//   can_always_end   from every reachable marking an exit stays reachable
//                    (for a mission net without exits: the end, nothing
//                    enabled, stays reachable; a phase without exits fails)
//   no_busy_cycle    no cycle of firings that issue nothing to wait for
//                    (the engine could fire round it for ever)
//   exits_exclusive  no marking holds two different exits
//   phase_depth      the PHASE calls below the net nest no deeper than the
//                    engine allows (kMaxPhaseDepth)
//
// One set of rules for verify and run: a property that would make a run
// unsafe (bounded, no_deadlock, can_always_end, no_busy_cycle,
// exits_exclusive, phase_depth) blocks `strata run` when it fails or is not
// decided; one_safe and no_dead are information (warnings).
//
// Limits: each step (the graph, each property, the P-semiflows) stops at
// max_states, at max_memory_bytes (the process's resident memory, counted
// from what it holds when the step starts) and at the time limit, and out
// of memory; what it could not decide is then Undecided, never Fails.
//
// Each failed property carries the shortest firing sequence that shows it,
// in the mission's own names. Place bounds, the exits reachable and the
// P-invariants (minimal P-semiflows) of the analysis net come with it.
//
// Phases are verified before the nets that call them; a PHASE action's
// outcomes are then only the exits its phase can reach.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "coral/analysis.h"
#include "coral/program.h"
#include "coral/timing.h"
#include "coral/trace_step.h"
#include "core/source.h"

namespace strata::coral {

// The memory verification may use by default (the whole process's resident
// memory), for `strata verify` and `strata run` alike.
inline constexpr std::size_t kDefaultVerifyMemoryBytes = std::size_t{768} << 20;

// Where a result is about, in the mission's text (line 0: not known).
struct Location {
  std::string file;
  std::uint32_t line = 0, col = 0;
  std::string kind;  // "net", "place" or "transition"
  std::string name;
};

struct VerifyOptions {
  std::uint64_t max_states = 1'000'000;                      // per net
  std::size_t max_memory_bytes = kDefaultVerifyMemoryBytes;  // 0: no limit
  double time_limit_s = 0;                                   // for the whole verification; 0: none
  // Only the mission net and the phases it calls, directly or not (what a
  // run can reach); otherwise every net of the load.
  bool mission_only = false;
  // Resolves the results' locations to line and column (null: file only).
  const core::SourceManager* sources = nullptr;
  // The vehicle's timing, for the mission's `require` (a property
  // "requirement" each); nullopt: a requirement is not decided.
  std::optional<BoundOptions> timing = std::nullopt;
};

struct Counterexample {
  std::vector<TraceStep> steps;
  std::string marking;                     // mission places at the end: "a:1 b:2", or "(empty)"
  std::vector<std::string> in_flight;      // "ASK depth_reached (check_depth)"
  std::optional<std::size_t> repeat_from;  // bounded: the steps from here on repeat for ever
  // A requirement's: the timing analysis's path (the worst case, or the
  // way to an unbounded cycle) across the mission's nets, with times. Not a
  // witness: a run cannot follow it by scripted answers.
  bool timed = false;
};

struct Property {
  enum class Status { Holds, Fails, Undecided };
  std::string key;  // bounded, one_safe, ...
  Status status = Status::Holds;
  // True for a property whose failure makes a run unsafe; false for one that
  // only informs (one_safe, no_dead).
  bool blocking = true;
  // What the property is about: the place or the (mission) transition that
  // shows the failure, else the net.
  enum class About { Net, Place, Transition } about = About::Net;
  std::uint32_t about_id = 0;  // a PlaceId of the analysis net, or a mission TransitionId
  Location at;                 // resolved from `about`
  std::string message;         // for people: what holds, or what goes wrong
  std::optional<Counterexample> counterexample;
};

struct PlaceBound {
  Location at;
  std::string name;
  std::uint64_t bound = 0;
  bool in_flight = false;  // an in-flight place of the analysis net
};

struct Invariant {
  std::vector<std::pair<std::string, std::uint64_t>> weights;  // place name, weight
  std::uint64_t constant = 0;                                  // y.M0
};

struct NetVerification {
  std::string name;
  std::string kind;  // "phase" or "mission"
  std::string file;
  Location at;                                     // the `net NAME` / `mission NAME` head
  std::size_t places = 0, transitions = 0;         // of the mission's net
  std::size_t in_flight_places = 0, outcomes = 0;  // added by the analysis
  std::uint64_t states = 0, edges = 0;
  bool complete = true;
  std::string stopped_why;
  std::vector<PlaceBound> bounds;    // every analysis place (unbounded: the most seen)
  std::vector<std::string> exits;    // in order
  std::vector<bool> exit_reachable;  // by exit index
  std::vector<Property> properties;  // in the order listed above
  std::vector<Invariant> invariants;
  bool invariants_complete = true;
  std::string invariants_skipped;      // when not complete: why ("more than 2000 rows")
  std::vector<std::string> uncovered;  // places no P-semiflow covers

  // No blocking property fails or is undecided: the net may run.
  bool ok() const;
  // Every property holds, warnings included.
  bool all_hold() const;
};

struct VerifyReport {
  std::vector<NetVerification> nets;  // phases before their callers
  bool ok() const;                    // every net may run
  bool all_hold() const;
};

// Step t of the analysis net `an` (built for a net of `program`) in the
// mission's names, as counterexamples give it.
TraceStep trace_step(const Program& program, const AnalysisNet& an, petri::TransitionId t);

VerifyReport verify_program(const Program& program, const VerifyOptions& options = {});

// The exits each fully explored phase of the report can reach, for
// build_analysis_net (and export) to build the nets the report explored.
std::vector<PhaseExits> reachable_phase_exits(const VerifyReport& report);

}  // namespace strata::coral
