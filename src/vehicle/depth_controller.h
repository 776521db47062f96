#pragma once
// The Execution level's depth laws: they turn an estimate of depth and depth
// rate into a total thrust command (N, positive down), once a cycle.
//
// Depth: a sliding-mode law with a boundary layer (Healey & Lienard's form
// for the NPS vehicles). With the sliding surface
//     s = w + lambda (z - z_d)
// and the heave model (m + m_a) dw/dt = T - B - c w|w| (heave.h), choosing
//     T = (m + m_a)(-lambda w) + B + c w|w| - K sat(s / phi)
// cancels the modelled dynamics and leaves (m + m_a) ds/dt = -K sat(s/phi):
// s is driven into the layer |s| < phi in finite time (outside it at rate
// K / (m + m_a)) and decays exponentially inside it, with time constant
// (m + m_a) phi / K. On s = 0 the depth error decays as exp(-lambda t), so
// the law dives at the thrusters' limit while far away and eases in without
// overshoot. The thruster lag, the filter and the thrust limit are the
// unmodelled parts; the boundary layer absorbs them instead of chattering.
// The command is clamped to the nominal total thrust (both thrusters).
//
// Surface: thrusters full up until the depth estimate is at or above
// surface_depth_m, then off; the positive buoyancy keeps the vehicle there.
// It does not need the filter: it works on the raw reading too, and with no
// reading at all it keeps pushing up.
#include <optional>

#include "vehicle/params.h"

namespace strata::vehicle {

// Thrust command toward depth z_d_m from estimate (z_m, w_mps).
double sliding_mode_thrust(const VehicleParams& p, double z_m, double w_mps, double z_d_m);

// Thrust command of the surface law for a depth estimate (nullopt: none).
double surface_thrust(const VehicleParams& p, std::optional<double> z_m);

}  // namespace strata::vehicle
