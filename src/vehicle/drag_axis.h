#pragma once
// One horizontal axis of the vehicle (surge, sway): a force that follows
// its command with a first-order lag, against quadratic drag.
#include <algorithm>
#include <cmath>

namespace strata::vehicle {

struct DragAxis {
  double lag_s = 0.0;       // the force's time constant (0: at once)
  double drag_coeff = 0.0;  // N per (m/s)^2
  double mass_kg = 1.0;     // with added mass
};

// Advances force_n and speed_mps by one sub-step of h_s: the force towards
// the command clamped to +-limit_n (the lag exactly), then the speed by the
// force less the drag (semi-implicit Euler).
inline void advance_drag_axis(const DragAxis& a, double cmd_n, double limit_n, double h_s, double& force_n,
                              double& speed_mps) {
  const double target = std::clamp(cmd_n, -limit_n, limit_n);
  const double lag = a.lag_s > 0.0 ? 1.0 - std::exp(-h_s / a.lag_s) : 1.0;
  force_n += (target - force_n) * lag;
  const double force = force_n - a.drag_coeff * speed_mps * std::abs(speed_mps);
  speed_mps += h_s * force / a.mass_kg;
}

}  // namespace strata::vehicle
