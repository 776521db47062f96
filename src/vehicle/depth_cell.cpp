#include "vehicle/depth_cell.h"

#include <cmath>
#include <numbers>

namespace strata::vehicle {

std::optional<double> DepthCell::sample(double true_depth_m, bool dropped) {
  const double n = standard_normal();
  if (dropped) return std::nullopt;
  return true_depth_m + noise_m_ * n;
}

double DepthCell::standard_normal() {
  // Uniform deviates in (0, 1) from the top 53 bits; never 0, so log is finite.
  auto uniform = [this] { return (static_cast<double>(rng_() >> 11) + 0.5) * 0x1.0p-53; };
  const double u1 = uniform();
  const double u2 = uniform();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

}  // namespace strata::vehicle
