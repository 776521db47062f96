#include "vehicle/surge.h"

#include <algorithm>
#include <cmath>

#include "vehicle/drag_axis.h"

namespace strata::vehicle {

double speed_thrust_n(const VehicleParams& p, double speed_mps) {
  const double t = p.surge_drag_coeff * speed_mps * std::abs(speed_mps);
  return std::clamp(t, -p.max_surge_thrust_n(), p.max_surge_thrust_n());
}

void advance_surge(const VehicleParams& p, double thrust_cmd_n, double thrust_limit_n, double h_s, SurgeState& s) {
  advance_surge(p, thrust_cmd_n, thrust_limit_n, h_s, lag_fraction(h_s, p.motor_lag_s), s);
}

void advance_surge(const VehicleParams& p, double thrust_cmd_n, double thrust_limit_n, double h_s, double lag,
                   SurgeState& s) {
  advance_drag_axis({p.motor_lag_s, p.surge_drag_coeff, p.total_surge_mass_kg()}, thrust_cmd_n, thrust_limit_n, h_s,
                    lag, s.thrust_n, s.speed_mps);
}

}  // namespace strata::vehicle
