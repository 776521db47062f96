#include "vehicle/sway.h"

#include <algorithm>
#include <cmath>

#include "vehicle/drag_axis.h"

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
  advance_sway(p, force_cmd_n, force_limit_n, h_s, lag_fraction(h_s, p.transverse_lag_s), s);
}

void advance_sway(const VehicleParams& p, double force_cmd_n, double force_limit_n, double h_s, double lag,
                  SwayState& s) {
  advance_drag_axis({p.transverse_lag_s, p.sway_drag_coeff, p.total_sway_mass_kg()}, force_cmd_n, force_limit_n, h_s,
                    lag, s.force_n, s.speed_mps);
}

}  // namespace strata::vehicle
