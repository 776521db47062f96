#include "vehicle/navigation.h"

#include <cmath>

namespace strata::vehicle {

Navigator::Navigator(const VehicleParams& p, double x_m, double y_m, double sd_m)
    : walk_(p.nav_current_walk_mps * p.nav_current_walk_mps),
      speed_var_(p.nav_speed_sd_mps * p.nav_speed_sd_mps),
      x_(x_m),
      y_(y_m),
      ppp_(sd_m * sd_m),
      pcc_(p.nav_current_sd_mps * p.nav_current_sd_mps) {}

void Navigator::predict(double vx_water_mps, double vy_water_mps, double dt_s) {
  x_ += (vx_water_mps + cx_) * dt_s;
  y_ += (vy_water_mps + cy_) * dt_s;
  // P = F P F' + Q with F = [1 dt; 0 1]. The velocity error enters as a
  // random walk in position (speed_var * dt) that is at least linear in time
  // through the current's variance.
  ppp_ += dt_s * (2.0 * ppc_ + dt_s * pcc_) + speed_var_ * dt_s;
  ppc_ += dt_s * pcc_;
  pcc_ += walk_ * dt_s;
}

void Navigator::fix(double x_m, double y_m, double sd_m) {
  const double s = ppp_ + sd_m * sd_m;
  if (!(s > 0.0)) return;
  const double kp = ppp_ / s;
  const double kc = ppc_ / s;
  const double ex = x_m - x_;
  const double ey = y_m - y_;
  x_ += kp * ex;
  y_ += kp * ey;
  cx_ += kc * ex;
  cy_ += kc * ey;
  // P = (I - K H) P with H = [1 0].
  const double pp = ppp_, pc = ppc_;
  ppp_ = (1.0 - kp) * pp;
  ppc_ = (1.0 - kp) * pc;
  pcc_ -= kc * pc;
}

double Navigator::position_sd_m() const { return std::sqrt(2.0 * ppp_); }
double Navigator::current_sd_mps() const { return std::sqrt(pcc_); }

}  // namespace strata::vehicle
