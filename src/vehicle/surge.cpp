#include "vehicle/surge.h"

#include <algorithm>
#include <cmath>

namespace strata::vehicle {

double speed_thrust_n(const VehicleParams& p, double speed_mps) {
  const double t = p.surge_drag_coeff * speed_mps * std::abs(speed_mps);
  return std::clamp(t, -p.max_surge_thrust_n(), p.max_surge_thrust_n());
}

void advance_surge(const VehicleParams& p, double thrust_cmd_n, double thrust_limit_n, double h_s, SurgeState& s) {
  const double target = std::clamp(thrust_cmd_n, -thrust_limit_n, thrust_limit_n);
  const double lag = p.motor_lag_s > 0.0 ? 1.0 - std::exp(-h_s / p.motor_lag_s) : 1.0;
  s.thrust_n += (target - s.thrust_n) * lag;
  const double force = s.thrust_n - p.surge_drag_coeff * s.speed_mps * std::abs(s.speed_mps);
  s.speed_mps += h_s * force / p.total_surge_mass_kg();
}

}  // namespace strata::vehicle
