#pragma once
// The vehicle's surge (forward) motion through the water, from its two
// propulsion motors, whose total thrust follows the command through a
// first-order lag:
//
//   (m + m_a) du/dt = T - c u|u|,   tau dT/dt = T_c - T
//
// u (speed_mps) is the speed through the water along the bow (positive
// ahead), T the thrust (positive ahead). The water current carries the
// vehicle on top of u (simulation.h); it does not enter this equation.
//
// Speed law: feed-forward thrust T_c = c u_d|u_d| for the speed u_d asked
// for, clamped to the motors' limit. The steady speed is then u_d exactly
// (with nominal motors). From rest the speed rises as u_d tanh(t c u_d /
// (m + m_a)) (behind the motors' lag), with no overshoot: 63% after about
// 8 s for 0.8 m/s with the estimates in config/phoenix.toml; near the final
// speed it is first order with time constant (m + m_a) / (2 c u_d), 5 s.
#include "vehicle/params.h"

namespace strata::vehicle {

struct SurgeState {
  double speed_mps = 0.0;  // through the water, positive ahead
  double thrust_n = 0.0;   // actual total thrust of both motors

  bool operator==(const SurgeState&) const = default;
};

// The speed law's thrust command for speed_mps, N.
double speed_thrust_n(const VehicleParams& p, double speed_mps);

// Advances s by one sub-step of h_s (semi-implicit Euler; the lag exactly).
// thrust_limit_n (>= 0) clamps the command (nominal times health).
void advance_surge(const VehicleParams& p, double thrust_cmd_n, double thrust_limit_n, double h_s, SurgeState& s);
// The same, with the motors' lag_fraction(h_s, p.motor_lag_s) worked out already.
void advance_surge(const VehicleParams& p, double thrust_cmd_n, double thrust_limit_n, double h_s, double lag,
                   SurgeState& s);

}  // namespace strata::vehicle
