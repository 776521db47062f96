#include "vehicle/heave.h"

#include <algorithm>
#include <cmath>

#include "vehicle/drag_axis.h"

namespace strata::vehicle {

HeaveContact advance_heave(const VehicleParams& p, double thrust_cmd_n, double thrust_limit_n, HeaveState& s) {
  return advance_heave(p, thrust_cmd_n, thrust_limit_n, p.tank_depth_m, s);
}

HeaveContact advance_heave(const VehicleParams& p, double thrust_cmd_n, double thrust_limit_n, double bottom_m,
                           HeaveState& s) {
  const double h = p.cycle_s / p.substeps;
  const double target = std::clamp(thrust_cmd_n, -thrust_limit_n, thrust_limit_n);
  // Exact step of tau dT/dt = target - T over h; a zero lag follows at once.
  const double lag = lag_fraction(h, p.thruster_lag_s);
  const double mass = p.total_mass_kg();
  HeaveContact contact;
  for (int i = 0; i < p.substeps; ++i) {
    s.thrust_n += (target - s.thrust_n) * lag;
    const double force = s.thrust_n - p.buoyancy_n - p.drag_coeff * s.w_mps * std::abs(s.w_mps);
    s.w_mps += h * force / mass;
    s.depth_m += h * s.w_mps;  // semi-implicit: the new velocity moves the body
    contact = {};
    if (s.depth_m <= 0.0) {
      s.depth_m = 0.0;
      s.w_mps = std::max(s.w_mps, 0.0);
      contact.surface = true;
    } else if (s.depth_m >= bottom_m) {
      s.depth_m = bottom_m;
      s.w_mps = std::min(s.w_mps, 0.0);
      contact.bottom = true;
    }
  }
  return contact;
}

}  // namespace strata::vehicle
