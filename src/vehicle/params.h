#pragma once
// Parameters of the simulated NPS Phoenix in a test tank or in open water
// (heave, yaw, surge, navigation, a scanning sonar and a sonar altimeter),
// with units in the names. The values are ESTIMATES
// (docs/open_water.md), not Phoenix data: config/phoenix.toml carries the same
// values, commented.
//
// Sign conventions used throughout strata::vehicle: depth and heave rate are
// positive DOWN; thrust is positive when it pushes the vehicle down;
// buoyancy_n is the net upward force at rest (weight subtracted), so a
// slightly positively buoyant vehicle has buoyancy_n > 0 and floats up when
// the thrusters stop. Headings are compass degrees of the bow: 0 = tank +y,
// 90 = tank +x, clockwise seen from above, in [0, 360); yaw rate and yaw
// moment are positive clockwise (to starboard). The tank is the box
// [0, tank_length_x_m] x [0, tank_width_y_m] x [0, tank_depth_m]. In open
// water (scenario.h) the same axes hold: x is east, y is north, in metres
// from the scenario's origin; the seabed replaces the tank's floor.
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"

namespace strata::vehicle {

struct VehicleParams {
  // [hull]
  double mass_kg = 175.0;        // dry mass
  double added_mass_kg = 250.0;  // heave added mass (entrained water)
  double drag_coeff = 470.0;     // N per (m/s)^2: drag force = -drag_coeff * w * |w|
  double buoyancy_n = 5.0;       // net buoyancy, positive = upward

  // [thrusters] two vertical thrusters, identical
  double thruster_max_n = 18.0;  // per thruster, either direction
  double thruster_lag_s = 0.3;   // first-order time constant of the actual thrust

  // [depth_cell]
  double depth_noise_m = 0.02;  // standard deviation of the white measurement noise

  // [filter] alpha-beta filter on depth, run once a cycle
  double filter_alpha = 0.3;  // position gain, (0, 1]
  double filter_beta = 0.05;  // rate gain, (0, 2)

  // [controller] sliding-mode depth law with a boundary layer
  double ctrl_lambda_per_s = 0.5;  // sliding surface slope: s = w + lambda * (z - z_d)
  double ctrl_gain_n = 60.0;       // switching gain K
  double ctrl_phi_mps = 0.25;      // boundary layer half-width on s

  // [yaw] two transverse thrusters, fore and aft, pushing opposite ways:
  //   (I + I_a) dr/dt = M - c r|r|,  tau dM/dt = M_c - M
  double yaw_inertia_kgm2 = 66.0;        // hull: m L^2 / 12 = 175 * 2.13^2 / 12
  double yaw_added_inertia_kgm2 = 60.0;  // entrained water
  double yaw_drag_coeff = 40.0;          // N m per (rad/s)^2: moment = -c * r * |r|
  double transverse_max_n = 9.0;         // per transverse thruster, either direction
  double transverse_lever_m = 0.6;       // each thruster's distance from the yaw axis
  double transverse_lag_s = 0.3;         // first-order time constant of the thrust

  // [heading_controller] sliding-mode heading law with a boundary layer
  double hdg_lambda_per_s = 0.5;   // sliding surface: s = r - r_d, r_d = -lambda * e ...
  double hdg_max_rate_dps = 15.0;  // ... capped at this turn rate
  double hdg_gain_nm = 10.0;       // switching gain K
  double hdg_phi_dps = 3.0;        // boundary layer half-width on s

  // [simulation]
  double cycle_s = 0.1;       // Execution-level cycle (10 Hz)
  int substeps = 10;          // integration sub-steps per cycle
  double tank_depth_m = 6.0;  // the tank bottom; depth is clamped to [0, tank_depth_m]

  // [tank] the horizontal extent (the vehicle hovers: it does not move in x, y)
  double tank_length_x_m = 12.0;
  double tank_width_y_m = 8.0;

  // [surge] two propulsion motors, aft, pushing together:
  //   (m + m_a) du/dt = T - c u|u|,  tau dT/dt = T_c - T
  double surge_added_mass_kg = 20.0;  // surge added mass (slender body: small)
  double surge_drag_coeff = 24.0;     // N per (m/s)^2: drag = -c * u * |u|
  double motor_max_n = 12.0;          // per propulsion motor, ahead or astern
  double motor_lag_s = 0.5;           // first-order time constant of the thrust

  // [sway] the transverse thrusters pushing the same way (sway.h):
  //   (m + m_a) dv/dt = F - c v|v|, the thrust and its lag as in [yaw]
  double sway_added_mass_kg = 175.0;  // sway added mass (a slender body: about its displaced mass)
  double sway_drag_coeff = 220.0;     // N per (m/s)^2: cross-flow drag = -c * v * |v|

  // [navigation] dead reckoning from water speed and compass, GPS at the surface
  double gps_noise_m = 1.5;             // standard deviation of a fix, per axis
  double gps_period_s = 1.0;            // one fix per period while the antenna is dry
  double gps_max_depth_m = 0.3;         // the antenna is dry at or above this depth
  double nav_initial_sd_m = 10.0;       // open water: the launch position, per axis
  double nav_speed_sd_mps = 0.05;       // dead reckoning error rate (speed, heading), per axis
  double nav_current_sd_mps = 0.3;      // the current before any fix, per axis
  double nav_current_walk_mps = 0.002;  // how fast the current may change, per sqrt(s)
  double position_limit_m = 25.0;       // position_uncertain: horizontal 1-sigma above this

  // [guidance] line of sight to a waypoint or along a track line
  double los_lookahead_m = 8.0;    // the aim point this far ahead along the line
  double waypoint_radius_m = 3.0;  // waypoint_reached: estimated distance below this
  double cruise_speed_mps = 0.8;   // goto_xy / track when no speed was set
  double max_depth_m = 50.0;       // open water: deepest goto_depth / setpoint accepted

  // [altimeter] downward sonar altimeter
  double altimeter_range_m = 30.0;  // no echo farther than this
  double altimeter_noise_m = 0.05;  // standard deviation of a reading
  double altitude_floor_m = 2.0;    // altitude_low: a reading below this (default floor)

  // [sonar] forward-looking mechanically scanned sonar (ST1000-like)
  double sonar_beam_width_deg = 1.8;    // one conical beam
  double sonar_step_deg = 1.8;          // head step per ping
  double sonar_sector_half_deg = 60.0;  // sweeps back and forth over +-this about the bow
  double sonar_ping_period_s = 0.05;    // rounded to whole integration sub-steps
  double sonar_range_m = 10.0;
  int sonar_bins = 200;                  // echo intensity bins (u8) over the range
  double sonar_noise = 6.0;              // mean background intensity (exponential), counts
  double sonar_wall_echo = 180.0;        // a wall at normal incidence, counts
  double sonar_target_echo = 200.0;      // the target at normal incidence, counts
  int sonar_buffer_pings = 1024;         // pings held for take_pings(); older ones dropped
  double sonar_detect_threshold = 90.0;  // target_detected: a bin at least this ...
  double sonar_detect_margin_m = 0.5;    // ... this much short of the wall ...
  int sonar_detect_min_pings = 2;        // ... in this many pings of the last sweep

  // [detection]
  double depth_tolerance_m = 0.1;      // depth_reached: |z - z_d| < this ...
  double settle_rate_mps = 0.05;       // ... and |rate| < this
  double surface_depth_m = 0.15;       // surface_reached: depth <= this
  double heading_tolerance_deg = 3.0;  // heading_reached: |heading error| < this ...
  double heading_settle_dps = 2.0;     // ... and |yaw rate| < this

  // [watchdog]
  double watchdog_s = 3.0;  // link silence after which the vehicle surfaces itself

  double total_mass_kg() const { return mass_kg + added_mass_kg; }
  // Largest total thrust both thrusters give at full health, N.
  double max_total_thrust_n() const { return 2.0 * thruster_max_n; }
  double total_yaw_inertia_kgm2() const { return yaw_inertia_kgm2 + yaw_added_inertia_kgm2; }
  // Largest yaw moment of both transverse thrusters at full health, N m.
  double max_yaw_moment_nm() const { return 2.0 * transverse_max_n * transverse_lever_m; }
  double total_surge_mass_kg() const { return mass_kg + surge_added_mass_kg; }
  // Largest total thrust of both propulsion motors at full health, N.
  double max_surge_thrust_n() const { return 2.0 * motor_max_n; }
  double total_sway_mass_kg() const { return mass_kg + sway_added_mass_kg; }
  // Largest sway force of both transverse thrusters at full health, N.
  double max_sway_force_n() const { return 2.0 * transverse_max_n; }
  // Steady sway speed at full force (no yaw moment asked), m/s.
  double top_sway_speed_mps() const {
    return sway_drag_coeff > 0.0 ? std::sqrt(max_sway_force_n() / sway_drag_coeff) : max_sway_force_n();
  }
  // Steady speed at full thrust, m/s: where drag equals thrust.
  double top_speed_mps() const {
    return surge_drag_coeff > 0.0 ? std::sqrt(max_surge_thrust_n() / surge_drag_coeff) : max_surge_thrust_n();
  }

  bool operator==(const VehicleParams&) const = default;
};

// The built-in values (the same as config/phoenix.toml).
inline VehicleParams default_params() { return VehicleParams{}; }

// Parses a parameter file. Every key must be present (the shipped file is the
// template), unknown tables or keys are errors, and each value is range
// checked. Errors are ErrorCode::InvalidInput with "path:line:col: message"
// (or "path: message" for a missing key); a file that cannot be read is
// ErrorCode::Io.
core::Result<VehicleParams> load_params(std::string_view path);
// The same, from text in memory; path is used in messages only.
core::Result<VehicleParams> parse_params(std::string_view text, std::string_view path);

// One parameter by its name in config/phoenix.toml ("hull.mass_kg") and its
// admissible range (lo < v or lo <= v; v <= hi; whole numbers when integer),
// the same the file is checked against.
struct ParamInfo {
  std::string name;
  double lo = 0.0;
  bool lo_open = false;
  double hi = 0.0;
  bool integer = false;
};
// Every parameter, in the file's order.
const std::vector<ParamInfo>& param_infos();
// The parameter named so; nullptr when there is none.
const ParamInfo* find_param(std::string_view name);
// "0 < value", "0 <= value <= 1", "any finite value": the range, for messages.
std::string param_range_text(const ParamInfo& info);
// Why v cannot be the parameter's value ("" when it can): not finite, out
// of range, not whole.
std::string param_value_problem(const ParamInfo& info, double v);
// "hull: mass_kg, added_mass_kg, ...; thrusters: max_n, lag_s; ...": every
// name, for messages.
std::string param_names_text();

// Sets one parameter by name (overrides: a campaign's perturbations).
// InvalidInput, naming it, for an unknown name or a value it cannot take.
core::Result<void> set_param(VehicleParams& p, std::string_view name, double value);
// The rules between parameters a file must also meet (the surface above the
// tank's bottom, the cruise speed within the top speed). InvalidInput with why.
core::Result<void> check_param_relations(const VehicleParams& p);
// Whether the parameter takes part in those rules.
bool param_in_relations(std::string_view name);
// The parameters as a complete parameter file (`strata run --params`
// reads it back to the same values).
std::string params_toml(const VehicleParams& p);

}  // namespace strata::vehicle
