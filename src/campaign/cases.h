#pragma once
// The cases of a campaign, addressed by index 0..N-1 (design: the same index
// contract runs locally, on Slurm job arrays, GNU parallel or Kubernetes
// Indexed Jobs). The order is fixed by the spec alone: missions in the order
// listed, then families in file order, then the family's axes (at_s
// outermost, then health, then duration_s, then each perturbed vehicle
// parameter), then seeds. case_at(spec, i) is
// computed, not looked up: any process with the spec finds case i by itself.
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "campaign/spec.h"
#include "core/result.h"
#include "vehicle/params.h"
#include "vehicle/scenario.h"

namespace strata::campaign {

struct Case {
  std::uint64_t index = 0;
  std::size_t mission = 0;  // into Spec::missions
  std::size_t family = 0;   // into Spec::families
  std::optional<vehicle::Fault> fault;
  // The family's perturbed vehicle parameters and this case's values, in
  // the family's order; the rest of the vehicle is config/phoenix.toml's.
  std::vector<std::pair<std::string, double>> params;
  std::uint64_t seed = 1;
};

// Case i of the spec; i < spec.case_count().
Case case_at(const Spec& spec, std::uint64_t index);

// The vehicle scenario of a case, as TOML (vehicle/scenario.h's format): the
// run reads it in memory, and a failing case's copy lets `strata run
// --scenario FILE` reproduce it.
std::string scenario_toml(const Spec& spec, const Case& c);

// The case's inputs for results.jsonl and --list: mission, family, fault
// (kind, at_s, health, duration_s), seed.
nlohmann::ordered_json case_inputs(const Spec& spec, const Case& c);

// "leak at 4 s", "weak_thrusters health 0.4 at 2 s", "none": one line for people.
std::string fault_text(const Case& c);
// "hull.mass_kg=172.5 thrusters.max_n=15": the perturbed parameters; "" none.
std::string params_text(const Case& c);
// The case's vehicle parameters: the spec's (its parameter file, or the
// built-in ones) with the case's perturbations. The spec was checked, so
// every value is one the vehicle takes.
vehicle::VehicleParams case_params(const Spec& spec, const Case& c);

// An index range "A-B" or "I" (inclusive) within [0, count). Errors name the count.
struct IndexRange {
  std::uint64_t first = 0;
  std::uint64_t last = 0;  // inclusive
};
core::Result<IndexRange> parse_range(const std::string& text, std::uint64_t count);

}  // namespace strata::campaign
