#pragma once
// `strata verify MISSION --bound 'FROM -> TO [within S]'`: the reaction time
// (coral/timing.h, docs/verification.md "Reaction time").
#include <cstdint>
#include <string>
#include <vector>

namespace strata::cli {

struct BoundFlags {
  std::vector<std::string> questions;  // --bound, each as written
  double depth_max_m = 6.0;            // --depth-max: the ascent estimate's start
};

// Answers each question of flags about the mission; the exit code: 0 when
// each is bounded (within its S, when given), 65 when one is not, 64 for a
// question that does not parse or names what the mission lacks.
int run_mission_bounds(const std::string& mission, const std::string& catalogue, const BoundFlags& flags,
                       const std::string& format, std::uint64_t max_states, bool verbose);

}  // namespace strata::cli
