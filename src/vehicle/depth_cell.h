#pragma once
// The pressure depth cell: true depth plus white Gaussian noise, or no
// reading while a dropout fault is active. The noise comes from a
// std::mt19937_64 seeded by the scenario, turned into normal deviates by our
// own Box-Muller transform (std::normal_distribution differs between
// standard libraries; this does not), so a seed gives the same readings
// everywhere. One deviate is drawn per sample whether or not the reading is
// dropped, so a dropout does not shift the noise of later samples.
#include <cstdint>
#include <optional>
#include <random>

namespace strata::vehicle {

class DepthCell {
 public:
  DepthCell(double noise_m, std::uint64_t seed) : noise_m_(noise_m), rng_(seed) {}

  // A reading of true_depth_m (m, positive down), or nullopt if dropped.
  // Readings are not clamped: at the surface they scatter around zero.
  std::optional<double> sample(double true_depth_m, bool dropped);

 private:
  double standard_normal();

  double noise_m_;
  std::mt19937_64 rng_;
};

}  // namespace strata::vehicle
