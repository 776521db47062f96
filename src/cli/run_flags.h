#pragma once
// The flags of a run that `strata run` and `strata compare` both take, with
// one spelling, one help text and one range (compare applies them to both
// of its runs).
#include <CLI/CLI.hpp>

#include "cli/validators.h"

#include "run/options.h"

namespace strata::cli {

inline void add_shared_run_flags(CLI::App* cmd, run::RunOptions& o) {
  cmd->add_option("--data", o.data, "Mission data file (default: the one the mission names)");
  cmd->add_option(
         "--max-sim-time", o.max_sim_time_s,
         "Lockstep, or an IMC vehicle's clock: end the run (an abort: the vehicle is surfaced) after this many "
         "simulated seconds")
      ->check(finite_range(1.0, 1e9))
      ->capture_default_str();
  cmd->add_option("--telemetry-hz", o.telemetry_hz, "Telemetry asked of the vehicle, per simulated second")
      ->check(finite_range(0.0, 100.0))
      ->capture_default_str();
}

}  // namespace strata::cli
