#pragma once
// One horizontal axis of the vehicle (surge, sway): a force that follows
// its command with a first-order lag, against quadratic drag.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

namespace strata::vehicle {

struct DragAxis {
  double lag_s = 0.0;       // the force's time constant (0: at once)
  double drag_coeff = 0.0;  // N per (m/s)^2
  double mass_kg = 1.0;     // with added mass
};

// The fraction of the way a first-order lag of lag_s goes in h_s:
// 1 - exp(-h_s / lag_s); 1 with no lag. The same for every sub-step of a
// run, so the simulation works it out once a cycle, not once a sub-step.
inline double lag_fraction(double h_s, double lag_s) { return lag_s > 0.0 ? 1.0 - std::exp(-h_s / lag_s) : 1.0; }

// x is +0.0 exactly (not -0.0): the value an axis at rest holds.
inline bool plus_zero(double x) { return std::bit_cast<std::uint64_t>(x) == 0; }

// Advances force_n and speed_mps by one sub-step of h_s: the force towards
// the command clamped to +-limit_n (the lag exactly; lag is
// lag_fraction(h_s, a.lag_s)), then the speed by the force less the drag
// (semi-implicit Euler).
inline void advance_drag_axis(const DragAxis& a, double cmd_n, double limit_n, double h_s, double lag, double& force_n,
                              double& speed_mps) {
  const double target = std::clamp(cmd_n, -limit_n, limit_n);
  // At rest and asked for nothing, the step would leave both as they are,
  // bit for bit for finite parameters (+0 stays +0 through every term
  // below): skipped.
  if (target == 0.0 && plus_zero(force_n) && plus_zero(speed_mps)) return;
  force_n += (target - force_n) * lag;
  const double force = force_n - a.drag_coeff * speed_mps * std::abs(speed_mps);
  speed_mps += h_s * force / a.mass_kg;
}

}  // namespace strata::vehicle
