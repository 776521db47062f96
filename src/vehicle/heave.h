#pragma once
// The vehicle's heave (vertical) motion: one rigid body with added mass,
// quadratic drag, net buoyancy and two vertical thrusters whose total thrust
// follows the command through a first-order lag.
//
//   (m + m_a) dw/dt = T - B - c w|w|,   dz/dt = w,   tau dT/dt = T_c - T
//
// z (depth_m) and w (w_mps) are positive down, T positive pushes down, B is
// the net upward buoyancy (VehicleParams). The water surface (z = 0) and the
// tank bottom (z = tank_depth_m) are hard limits: the depth is clamped and a
// velocity that would leave the water column is zeroed.
#include "vehicle/params.h"

namespace strata::vehicle {

struct HeaveState {
  double depth_m = 0.0;
  double w_mps = 0.0;
  double thrust_n = 0.0;  // actual total thrust of both thrusters

  bool operator==(const HeaveState&) const = default;
};

struct HeaveContact {
  bool surface = false;  // held at z = 0 at the end of the cycle
  bool bottom = false;   // held at z = tank_depth_m at the end of the cycle
};

// Advances s by one cycle (p.cycle_s in p.substeps semi-implicit Euler
// steps; the lag is integrated exactly per sub-step). thrust_cmd_n is the
// controller's command, held over the cycle; thrust_limit_n (>= 0) is what
// the thrusters can give now (nominal total times health) and clamps it.
HeaveContact advance_heave(const VehicleParams& p, double thrust_cmd_n, double thrust_limit_n, HeaveState& s);
// The same over a bottom at bottom_m (>= 0) instead of the tank's floor: the
// seabed under the vehicle in open water.
HeaveContact advance_heave(const VehicleParams& p, double thrust_cmd_n, double thrust_limit_n, double bottom_m,
                           HeaveState& s);

}  // namespace strata::vehicle
