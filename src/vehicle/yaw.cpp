#include "vehicle/yaw.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/units.h"
#include "vehicle/drag_axis.h"

namespace strata::vehicle {

using core::kRadPerDeg;

double wrap_heading_deg(double deg) {
  double w = std::fmod(deg, 360.0);
  if (w < 0.0) w += 360.0;
  return w >= 360.0 ? 0.0 : w;  // -1e-17 + 360 rounds to 360
}

double heading_error_deg(double heading_deg, double target_deg) {
  return wrap_heading_deg(heading_deg - target_deg + 180.0) - 180.0;
}

void advance_yaw(const VehicleParams& p, double moment_cmd_nm, double moment_limit_nm, double h_s, YawState& s) {
  advance_yaw(p, moment_cmd_nm, moment_limit_nm, h_s, lag_fraction(h_s, p.transverse_lag_s), s);
}

void advance_yaw(const VehicleParams& p, double moment_cmd_nm, double moment_limit_nm, double h_s, double lag,
                 YawState& s) {
  const double target = std::clamp(moment_cmd_nm, -moment_limit_nm, moment_limit_nm);
  s.moment_nm += (target - s.moment_nm) * lag;
  double r = s.rate_dps * kRadPerDeg;
  r += h_s * (s.moment_nm - p.yaw_drag_coeff * r * std::abs(r)) / p.total_yaw_inertia_kgm2();
  s.rate_dps = r / kRadPerDeg;
  s.heading_deg = wrap_heading_deg(s.heading_deg + h_s * s.rate_dps);
}

double heading_moment(const VehicleParams& p, double heading_deg, double rate_dps, double target_deg) {
  const double r = rate_dps * kRadPerDeg;
  const double e = heading_error_deg(heading_deg, target_deg) * kRadPerDeg;
  // The rate the surface asks for, -lambda e, capped at the turn rate.
  const double cap = p.hdg_max_rate_dps * kRadPerDeg;
  const bool linear = std::abs(p.hdg_lambda_per_s * e) < cap;
  const double r_d = std::clamp(-p.hdg_lambda_per_s * e, -cap, cap);
  const double s = r - r_d;
  const double sat = std::clamp(s / (p.hdg_phi_dps * kRadPerDeg), -1.0, 1.0);
  // d(r_d)/dt = -lambda r on the linear part, 0 where capped.
  const double moment = p.total_yaw_inertia_kgm2() * (linear ? -p.hdg_lambda_per_s * r : 0.0) +
                        p.yaw_drag_coeff * r * std::abs(r) - p.hdg_gain_nm * sat;
  const double limit = p.max_yaw_moment_nm();
  return std::clamp(moment, -limit, limit);
}

}  // namespace strata::vehicle
