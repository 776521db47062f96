#include "vehicle/sway.h"

#include <algorithm>
#include <cmath>

namespace strata::vehicle {

double sway_force_n(const VehicleParams& p, double speed_mps) {
  const double f = p.sway_drag_coeff * speed_mps * std::abs(speed_mps);
  return std::clamp(f, -p.max_sway_force_n(), p.max_sway_force_n());
}

double sway_force_limit_n(const VehicleParams& p, double moment_nm, double health) {
  const double taken = p.transverse_lever_m > 0.0 ? std::abs(moment_nm) / p.transverse_lever_m : 0.0;
  return std::max(0.0, p.max_sway_force_n() * health - taken);
}

void advance_sway(const VehicleParams& p, double force_cmd_n, double force_limit_n, double h_s, SwayState& s) {
  const double target = std::clamp(force_cmd_n, -force_limit_n, force_limit_n);
  const double lag = p.transverse_lag_s > 0.0 ? 1.0 - std::exp(-h_s / p.transverse_lag_s) : 1.0;
  s.force_n += (target - s.force_n) * lag;
  const double force = s.force_n - p.sway_drag_coeff * s.speed_mps * std::abs(s.speed_mps);
  s.speed_mps += h_s * force / p.total_sway_mass_kg();
}

}  // namespace strata::vehicle
