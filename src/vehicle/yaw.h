#pragma once
// The vehicle's yaw (heading) motion and the heading law.
//
// Two transverse thrusters, one fore and one aft at transverse_lever_m from
// the yaw axis, push opposite ways, so they turn the vehicle without moving
// it. Their yaw moment follows the command through a first-order lag:
//
//   (I + I_a) dr/dt = M - c r|r|,   dpsi/dt = r,   tau dM/dt = M_c - M
//
// psi is the compass heading of the bow (params.h: 0 = tank +y, 90 = tank
// +x, clockwise), r the yaw rate, M the moment, all positive clockwise.
// Angles are in degrees outside and radians inside the dynamics (c is per
// (rad/s)^2).
//
// Heading law: a sliding-mode law with a boundary layer, like the depth law
// (depth_controller.h), on the heading error e = psi - psi_d wrapped to
// [-180, 180), so the vehicle always turns the short way round. The sliding
// surface asks for a yaw rate r_d = -lambda e capped at +-max_rate:
//     s = r - r_d(e)
// and M = (I + I_a) r_d'(e) r + c r|r| - K sat(s / phi) (r_d' = -lambda, or
// 0 where capped) leaves (I + I_a) ds/dt = -K sat(s / phi). A long turn runs
// at the capped rate, then eases in along s = 0, where e decays as
// exp(-lambda t). Without the cap the turn rate would be held near
// K / ((I + I_a) lambda), about 9 deg/s here, by the cancelling term. The
// cap is chosen so the thrusters can still brake from it without overshoot.
// The heading and yaw rate it uses are the true ones: the Phoenix's compass
// and rate gyro are taken as perfect here.
#include "vehicle/params.h"

namespace strata::vehicle {

struct YawState {
  double heading_deg = 0.0;  // [0, 360)
  double rate_dps = 0.0;     // yaw rate, deg/s, clockwise positive
  double moment_nm = 0.0;    // actual yaw moment of both transverse thrusters

  bool operator==(const YawState&) const = default;
};

// deg wrapped to [0, 360).
double wrap_heading_deg(double deg);
// heading - target wrapped to [-180, 180): negative means turn clockwise.
double heading_error_deg(double heading_deg, double target_deg);

// Advances s by one integration sub-step of h_s (semi-implicit Euler; the lag
// exactly). moment_cmd_nm is the law's command; moment_limit_nm (>= 0) is
// what the thrusters can give now and clamps it.
void advance_yaw(const VehicleParams& p, double moment_cmd_nm, double moment_limit_nm, double h_s, YawState& s);
// The same, with the transverse thrusters' lag_fraction(h_s,
// p.transverse_lag_s) worked out already.
void advance_yaw(const VehicleParams& p, double moment_cmd_nm, double moment_limit_nm, double h_s, double lag,
                 YawState& s);

// The heading law's moment command toward target_deg, clamped to the nominal
// moment of both thrusters.
double heading_moment(const VehicleParams& p, double heading_deg, double rate_dps, double target_deg);

}  // namespace strata::vehicle
