#pragma once
// Simulation time is a whole number of cycles times cycle_s, so it carries
// rounding (3 * 0.1 != 0.3). Every "has time t reached time at" comparison in
// the vehicle model goes through here, with a tolerance far below a cycle.
namespace strata::vehicle {

inline constexpr double kTimeEpsilon_s = 1e-9;

inline bool time_reached(double t_s, double at_s) { return t_s >= at_s - kTimeEpsilon_s; }

}  // namespace strata::vehicle
