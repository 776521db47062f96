#pragma once
// A campaign spec (docs/campaigns.md): the missions, the fault space, the
// seeds and the expectations every run must meet, read from TOML.
//
//   name = "tank"                       # optional: a title for the report
//   missions = ["tank.coral", "tank.pl"]  # relative to the spec's folder
//   seeds = [1, 2, 3]                   # or { from = 1, count = 8 }
//   sample_seed = 7                     # the seed of every `sampled` axis
//   max_sim_time_s = 300                # each case's simulated-time limit
//   telemetry_hz = 10                   # how often the depth is sampled
//   [expect.NAME]                       # a named expectation set
//   outcomes = ["completed", "aborted"]
//   surface_within_s = 15.0             # at the surface within T s of the fault
//   max_depth_m = 2.0
//   no_stall = true
//   no_refused_exec = true
//   bound = "fault system_problem -> exec surface"   # a case later than the
//                                       # proven worst case fails the analysis
//   [[family]]                          # one fault kind and its axes
//   name = "leak"                       # unique; default: the fault kind
//   fault = "leak"                      # a vehicle fault kind, or "none"
//   at_s = { from = 0, to = 30, step = 1 }   # or { from, to, sampled = N },
//                                            # a list, or one number
//   health = { from = 0.4, to = 1.0, step = 0.2 }  # weak_thrusters
//   duration_s = 2.0                    # sensor_dropout, link_loss (or forever = true)
//   expect = "NAME"                     # default: "default"
//   missions = ["tank.coral"]           # only these of the spec's missions (default: all)
//   answers = "filter_on.json"          # scripted vehicle answers (`strata verify
//                                       # --witness-out`): each case follows that witness
//   perturb = { hull.mass_kg = { from = 170, to = 180, sampled = 4 }, thrusters.max_n = [15, 18] }
//                                       # vehicle parameters (config/phoenix.toml's names)
//                                       # as more axes; also at the top level, for every family
//
// Every problem is "spec:line:col: message" (core::TomlErrors: all of them,
// in file order). Reading the same text always gives the same spec: sampled
// axes are drawn from sample_seed with a generator of our own (splitmix64),
// not from the standard library's distributions, whose output is not fixed.
#include <algorithm>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"
#include "coral/timing.h"
#include "vehicle/params.h"
#include "vehicle/scenario.h"

namespace strata::campaign {

// The default limit on the cases one spec may make; --max-cases raises it.
inline constexpr std::uint64_t kDefaultMaxCases = 100'000;
// The largest simulated-time limit a case may have (a day).
inline constexpr double kMaxSimTimeLimitS = 86'400.0;

enum class MissionKind { Coral, Prolog };

struct Mission {
  std::string path;      // as the spec writes it
  std::string resolved;  // relative to the spec's folder (or absolute), as the run opens it
  MissionKind kind = MissionKind::Coral;
};

// What every case of a family must meet. Unset: not checked.
struct ExpectationSet {
  std::string name;
  std::vector<std::string> outcomes;       // allowed: "completed", "aborted", "failed"; empty: any
  std::optional<double> surface_within_s;  // the vehicle at the surface within this of the fault
  std::optional<double> max_depth_m;       // the deepest the vehicle may go
  bool no_stall = false;                   // the mission must not end stalled
  bool no_refused_exec = false;            // no EXEC refused or answered 0 (by the vehicle or a script)
  std::string guard;                       // this guard must trip after the fault ("" no check)
  std::optional<double> guard_within_s;    // ... within this of the fault's start (needs guard)
  // The timing analysis's question, from the fault (`fault ASK -> TO`):
  // every case's time from its fault to TO is checked against the proven
  // worst case (docs/campaigns.md, "Cross-checking a proven bound").
  std::optional<coral::BoundQuery> bound;
};

// The values one vehicle parameter takes across a family's cases.
struct Perturbation {
  std::string param;  // its name in config/phoenix.toml: "hull.mass_kg"
  std::vector<double> values;
};

// The most vehicle parameters one family may perturb.
inline constexpr std::size_t kMaxPerturbedParams = 16;

// The most distinct `bound` questions a spec may ask: each is a timing
// analysis of every mission (the survey's takes 0.2 s) before the cases.
inline constexpr std::size_t kMaxBounds = 16;

// One fault kind (or none) over its axes: the cases are every combination
// of at_s x health x duration_s x each perturbed parameter (an axis a kind
// does not use has one value).
struct Family {
  std::string name;
  std::optional<vehicle::FaultKind> fault;  // nullopt: no fault ("none")
  std::vector<double> at_s;                 // injection times, s
  std::vector<double> health;               // weak_thrusters: fraction of nominal thrust
  std::vector<double> duration_s;           // sensor_dropout, link_loss (empty with forever)
  bool forever = false;                     // link_loss for the rest of the run
  std::string expect;                       // the name of an ExpectationSet
  std::vector<std::size_t> missions;        // into Spec::missions; empty: every mission
  std::string answers;                      // an answers file as the spec writes it; "" none
  std::string answers_resolved;             // ... relative to the spec's folder, as the run opens it
  // The spec's top-level perturbations and the family's own (the family's
  // replace the spec's for the same parameter), in config/phoenix.toml's order.
  std::vector<Perturbation> perturb;

  bool applies_to(std::size_t mission) const {
    return missions.empty() || std::find(missions.begin(), missions.end(), mission) != missions.end();
  }

  // The fault combinations of this family (not counting seeds).
  std::uint64_t combinations() const;
};

struct Spec {
  std::string path;  // the spec file, as given
  std::string name;
  std::vector<Mission> missions;
  std::vector<Family> families;
  std::vector<std::uint64_t> seeds;
  std::map<std::string, ExpectationSet> expectations;
  std::uint64_t sample_seed = 1;
  double max_sim_time_s = 600.0;
  // How often the vehicle's depth is sampled for the expectations, per
  // simulated second: the resolution of time-to-surface, and a cost (at 10 Hz
  // telemetry is about a third of a tank case's CPU).
  double telemetry_hz = 10.0;
  // params = "FILE": the vehicle parameter file every case starts from (its
  // perturbations are set over it); "" for the built-in parameters.
  std::string params;
  std::string params_resolved;  // ... relative to the spec's folder, as the run opens it
  vehicle::VehicleParams base_params = vehicle::default_params();
  // world = "FILE": a scenario file whose [world], [seabed] and [vehicle]
  // every case's scenario carries (as TOML in world_toml); "" the tank.
  std::string world;
  std::string world_toml;

  // For each mission, the combinations of the families that apply to it;
  // summed, times the seeds.
  std::uint64_t case_count() const;
  // The combinations of the families that apply to mission m.
  std::uint64_t combinations_for(std::size_t mission) const;
  // Whether any family perturbs a vehicle parameter.
  bool perturbs() const {
    return std::any_of(families.begin(), families.end(), [](const Family& f) { return !f.perturb.empty(); });
  }
};

struct SpecLimits {
  std::uint64_t max_cases = kDefaultMaxCases;
};

// Reads and checks the spec at path. Errors: Io when the file cannot be
// read; InvalidInput with every located problem, one per line.
core::Result<Spec> load_spec(const std::string& path, const SpecLimits& limits = {});
// The same from text; path locates messages and resolves mission paths.
core::Result<Spec> parse_spec(std::string_view text, const std::string& path, const SpecLimits& limits = {});

// "completed" etc. are the outcomes an expectation may allow.
bool known_outcome(std::string_view outcome);

}  // namespace strata::campaign
