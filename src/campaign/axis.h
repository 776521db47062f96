#pragma once
// One axis of a campaign's fault space, as a spec writes it:
//   4.0                                  one value
//   [1.0, 2.5, 4.0]                      a list
//   { from = 0, to = 30, step = 0.5 }    a grid: from, from + step, ... <= to
//   { from = 0, to = 30, sampled = 20 }  N values drawn uniformly in [from, to]
// Sampled values come from a splitmix64 stream seeded by the spec's
// sample_seed and the axis's name, and are sorted: the same spec always gives
// the same values, and adding a family does not move another's.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "core/toml_reader.h"

namespace strata::campaign {

struct AxisRules {
  std::string what;          // "at_s", "health": for messages
  double min = 0.0;          // every value >= min ...
  double max = 1e300;        // ... and <= max
  bool zero_allowed = true;  // false: > min when min is 0
  std::uint64_t max_values = 100'000;
};

// The axis's values, or nullopt with the problems added to errors.
// `stream` names the axis for sampling ("leak.at_s").
std::optional<std::vector<double>> parse_axis(core::TomlErrors& errors, const toml::node& node, const AxisRules& rules,
                                              std::uint64_t sample_seed, const std::string& stream);

// The splitmix64 generator (Steele, Lea and Flood 2014): fixed output for a
// seed on every platform.
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next();
  // Uniform in [0, 1), 53 bits.
  double unit() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

 private:
  std::uint64_t state_;
};

// Case counts saturate at 2^64 - 1 rather than wrap.
inline constexpr std::uint64_t kSaturated = ~std::uint64_t{0};
inline constexpr std::uint64_t sat_mul(std::uint64_t a, std::uint64_t b) {
  return a != 0 && b > kSaturated / a ? kSaturated : a * b;
}

// FNV-1a of text: a stable seed from a name.
std::uint64_t stable_hash(const std::string& text);

}  // namespace strata::campaign
