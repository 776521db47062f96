#pragma once
// What one case's run showed, and the expectations checked against it. Each
// check keeps its figure (the number or word it judged) beside pass/fail,
// so a reader sees how far a case was from its limit.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "campaign/spec.h"

namespace strata::campaign {

// The outcome words of a case: the mission's outcome ("completed",
// "aborted", "failed"), or "error" (the mission never started: a load
// error) or "crashed" (the worker running it died or overran its time).
struct Observation {
  std::string outcome;
  std::string reason;      // the mission's reason, or the error
  std::string stopped_by;  // "limit" when the simulated-time limit ended it
  bool stalled = false;    // CORAL: no transition enabled, no action in flight
  double sim_time_s = 0.0;
  std::optional<double> max_depth_m;  // deepest depth-cell reading or final depth
  // The fault, when the case has one: its start, and whether the run
  // lasted that long (a fault after the end of the run never happened).
  std::optional<double> fault_at_s;
  bool fault_reached = false;
  // Seconds from the fault's start to the first sign of the vehicle at the
  // surface (depth <= the vehicle's surface_depth_m): the vehicle's depth
  // estimate in telemetry (the depth filter's, by which it answers
  // surface_reached; the depth cell's reading before the filter has one); when telemetry stopped (a lost link), the
  // vehicle's own log line "at the surface"; failing that, the vehicle's final state after the run, which bounds it
  // from above.
  std::optional<double> time_to_surface_s;
  std::string surface_seen;  // "telemetry", "vehicle log", "final state", or ""
  int refused_execs = 0;     // EXECs the vehicle refused or answered 0, or scripted answers failed
  std::string first_refused;
  // A family with scripted answers (`answers`): how many of its answers the
  // run used, of how many, and why it left the script ("" it did not).
  std::optional<std::size_t> answers_used;
  std::size_t answers_total = 0;
  std::string answers_diverged;
  std::string answers_first_unused;
  // The guards that tripped, in order, with when (simulated seconds).
  std::vector<std::pair<std::string, double>> guard_trips;
  // The expectation set's bound: when its TO first came at or after the
  // fault, and when it last came before it (the mission already reacting).
  std::optional<double> bound_to_at_s;
  std::optional<double> bound_to_before_s;
};

// The timing analysis's answer for an expectation set's bound and a case's
// mission (campaign/bound.h).
struct BoundProof {
  std::optional<double> worst_s;  // the proven worst case; nullopt: none
  bool ends_without = false;      // a run may end after the fault without TO
  bool measured_only = false;     // PROLOG rules: no analysis, the time is only measured
  std::string why;                // no worst case: why
};

struct Check {
  std::string name;  // the expectation: "outcome", "surface_within_s", ...
  bool pass = false;
  nlohmann::json figure;  // what was measured (null: nothing to measure)
  nlohmann::json limit;   // what was allowed
  std::string note;       // why it passed without a figure, or how it failed
};

// Every expectation the set holds, in a fixed order. A case that crashed or
// never started fails "ran" first, whatever the set. A case with scripted
// answers also checks "answers_followed": every answer used, the run never
// leaving the script (the witness's path really ran). A set with a bound
// checks "bound" against `proof` (nullptr: no proof was made): a case whose
// TO came later than the proven worst case is a failure of the analysis.
std::vector<Check> evaluate(const ExpectationSet& set, const Observation& seen, const BoundProof* proof = nullptr);

nlohmann::ordered_json to_json(const Check& check);

}  // namespace strata::campaign
