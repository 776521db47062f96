#pragma once
// Checks of option values shared by the commands.
#include <cmath>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

namespace strata::cli {

// CLI::Range for a number of seconds, a speed, a rate: also refuses nan and
// inf, which CLI::Range lets through (every comparison with nan is false).
inline CLI::Validator finite_range(double min, double max) {
  return CLI::Validator(
      [min, max](std::string& text) -> std::string {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(text, value)) return fmt::format("'{}' is not a number", text);
        if (!std::isfinite(value) || value < min || value > max) {
          return fmt::format("{} is not in {:g} to {:g}", text, min, max);
        }
        return {};
      },
      fmt::format("in [{:g} - {:g}]", min, max));
}

}  // namespace strata::cli
