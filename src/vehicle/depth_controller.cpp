#include "vehicle/depth_controller.h"

#include <algorithm>
#include <cmath>

namespace strata::vehicle {

double sliding_mode_thrust(const VehicleParams& p, double z_m, double w_mps, double z_d_m) {
  const double s = w_mps + p.ctrl_lambda_per_s * (z_m - z_d_m);
  const double sat = std::clamp(s / p.ctrl_phi_mps, -1.0, 1.0);
  const double thrust = p.total_mass_kg() * (-p.ctrl_lambda_per_s * w_mps) + p.buoyancy_n +
                        p.drag_coeff * w_mps * std::abs(w_mps) - p.ctrl_gain_n * sat;
  const double limit = p.max_total_thrust_n();
  return std::clamp(thrust, -limit, limit);
}

double surface_thrust(const VehicleParams& p, std::optional<double> z_m) {
  if (z_m && *z_m <= p.surface_depth_m) return 0.0;
  return -p.max_total_thrust_n();
}

}  // namespace strata::vehicle
