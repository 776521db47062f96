#pragma once
// The vehicle's sway (sideways) motion through the water, from the two
// transverse thrusters pushing the same way.
//
// The fore and aft transverse thrusters (thrusts T_f, T_a, positive to
// starboard, each within +-transverse_max_n times the thrusters' health)
// give a yaw moment M = (T_f - T_a) L and a sway force F = T_f + T_a, L the
// lever (yaw.h). The heading law keeps priority: its moment takes
// |M| / L of the thrusters' 2 T_max, and the sway force gets what is left,
//
//   |F| <= 2 T_max h - |M| / L   (h: health),
//
// which keeps each thruster within its limit. The force follows its command
// through the same first-order lag as the moment (each thruster's lag is
// linear, so the sum lags as the difference does):
//
//   (m + m_a,sway) dv/dt = F - c_sway v|v|,   tau dF/dt = F_c - F
//
// v (speed_mps) is the speed through the water toward starboard (the bow's
// heading + 90 degrees; negative: to port). The sway law is feed-forward,
// like the speed law (surge.h): F_c = c_sway v_d|v_d| for the speed v_d
// asked for, then clamped to what the heading law leaves. There is no
// coupling to yaw or surge in this model (a slender body's cross-coupling is
// neglected: an estimate, like the numbers in config/phoenix.toml).
#include "vehicle/params.h"

namespace strata::vehicle {

struct SwayState {
  double speed_mps = 0.0;  // through the water, positive to starboard
  double force_n = 0.0;    // actual sway force of both transverse thrusters

  bool operator==(const SwayState&) const = default;
};

// The sway law's force command for speed_mps, N (feed-forward, clamped to
// both thrusters' nominal force).
double sway_force_n(const VehicleParams& p, double speed_mps);

// The sway force both thrusters can give while giving the yaw moment
// moment_nm, at health (0..1): 2 T_max health - |M| / L, never below 0.
double sway_force_limit_n(const VehicleParams& p, double moment_nm, double health);

// Advances s by one sub-step of h_s (semi-implicit Euler; the lag exactly).
// force_limit_n (>= 0) clamps the command.
void advance_sway(const VehicleParams& p, double force_cmd_n, double force_limit_n, double h_s, SwayState& s);
// The same, with the transverse thrusters' lag_fraction(h_s,
// p.transverse_lag_s) worked out already.
void advance_sway(const VehicleParams& p, double force_cmd_n, double force_limit_n, double h_s, double lag,
                  SwayState& s);

}  // namespace strata::vehicle
