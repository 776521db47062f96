#pragma once
// The timing analysis checked against runs (docs/verification.md, "Reaction
// time"): the mission run in lockstep against the embedded vehicle with a
// fault at each given time, and the simulated seconds from the fault to the
// first call the question's TO names. A run whose time exceeds the proven
// worst case shows the analysis unsound.
#include <optional>
#include <string>
#include <vector>

#include "coral/timing.h"

namespace strata::cli {

struct MeasuredReaction {
  double fault_s = 0;
  std::optional<double> reaction_s;  // nullopt: no TO after the fault
  int exit_code = 0;
};

// `scenario_toml` is the world (a scenario file's text without faults); a
// `[[fault]] kind = FAULT_KIND, at_s = T` is added for each time. Logs go to
// `work_dir`, which must exist.
std::vector<MeasuredReaction> measure_reactions(const std::string& mission, const coral::BoundQuery& query,
                                                const std::string& fault_kind, const std::vector<double>& fault_times,
                                                const std::string& scenario_toml, const std::string& work_dir);

// The proven answer for the question about the mission, with the built-in
// catalogue; the message of what went wrong otherwise.
coral::BoundAnswer prove_bound(const std::string& mission, const coral::BoundQuery& query, double depth_max_m = 6.0);

}  // namespace strata::cli
