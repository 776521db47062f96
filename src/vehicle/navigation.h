#pragma once
// The vehicle's estimate of where it is in the plan: dead reckoning at the
// control rate from water speed and compass heading, corrected by GPS fixes
// taken at the surface.
//
// A small Kalman filter, the same on each axis (x east, y north): the state
// is the position and the water current's component along the axis,
//
//   p' = p + (v_water + c) dt,   c' = c (+ a slow random walk)
//
// and a fix measures p with noise gps_noise_m. Both axes see the same inputs'
// statistics and are fixed together, so they share one 2x2 covariance. A fix
// after a long dive resets the estimate (the gain is near 1); fixes at the
// surface, once a second, smooth the noise and learn the current, which dead
// reckoning under water then carries on using. Without fixes the current's
// uncertainty makes the position's grow about linearly in time.
//
// Pure value type, deterministic; the noise of a fix comes from the caller.
#include "vehicle/params.h"

namespace strata::vehicle {

class Navigator {
 public:
  // Starts at (x_m, y_m) with sd_m per axis (0: known exactly) and no
  // knowledge of the current beyond params.nav_current_sd_mps.
  Navigator(const VehicleParams& p, double x_m, double y_m, double sd_m);

  // Dead reckoning over dt_s with the water-relative velocity (m/s) the
  // vehicle measures (water speed meter along the compass heading).
  void predict(double vx_water_mps, double vy_water_mps, double dt_s);
  // A position fix (x_m, y_m) with noise sd_m per axis.
  void fix(double x_m, double y_m, double sd_m);

  double x_m() const { return x_; }
  double y_m() const { return y_; }
  double current_x_mps() const { return cx_; }
  double current_y_mps() const { return cy_; }
  // Horizontal 1-sigma of the position, m: sqrt(var_x + var_y).
  double position_sd_m() const;
  double current_sd_mps() const;

 private:
  double walk_;       // current random walk, (m/s)^2 per s
  double speed_var_;  // dead-reckoning velocity error, (m/s)^2
  double x_, y_, cx_ = 0.0, cy_ = 0.0;
  double ppp_, ppc_ = 0.0, pcc_;  // covariance: position, cross, current (per axis)
};

}  // namespace strata::vehicle
