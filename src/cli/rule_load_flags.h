#pragma once
// The flags of the limits on loading PROLOG rules, the same on check, run
// and compare (docs/prolog.md, "Limits").
#include <CLI/CLI.hpp>

#include "cli/validators.h"

#include "run/options.h"

namespace strata::cli {

inline void add_rule_load_flags(CLI::App* cmd, run::RuleLoadLimits& limits) {
  cmd->add_option("--load-time-limit", limits.time_s,
                  "PROLOG: seconds of wall clock the rules' load and check may take (directives included)")
      ->check(finite_range(0.1, 3600.0))
      ->capture_default_str();
  cmd->add_option("--load-inference-limit", limits.inferences,
                  "PROLOG: inferences the load may make (clauses read and directives run, together)")
      ->check(CLI::Range(std::uint64_t{1000}, std::uint64_t{1'000'000'000'000}))
      ->capture_default_str();
  cmd->add_option("--max-rules-size", limits.max_bytes, "PROLOG: bytes of each rule file; a larger file is not read")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{1} << 31))
      ->capture_default_str();
}

}  // namespace strata::cli
