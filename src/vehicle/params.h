#pragma once
// Parameters of the simulated NPS Phoenix in a test tank (heave only), with
// units in the names. The values are ESTIMATES (design.md §2.7), not Phoenix
// data: config/phoenix.toml carries the same values, commented.
//
// Sign conventions used throughout strata::vehicle: depth and heave rate are
// positive DOWN; thrust is positive when it pushes the vehicle down;
// buoyancy_n is the net upward force at rest (weight subtracted), so a
// slightly positively buoyant vehicle has buoyancy_n > 0 and floats up when
// the thrusters stop.
#include <string_view>

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
  double depth_noise_m = 0.02;   // standard deviation of the white measurement noise

  // [filter] alpha-beta filter on depth, run once a cycle
  double filter_alpha = 0.3;     // position gain, (0, 1]
  double filter_beta = 0.05;     // rate gain, (0, 2)

  // [controller] sliding-mode depth law with a boundary layer
  double ctrl_lambda_per_s = 0.5;  // sliding surface slope: s = w + lambda * (z - z_d)
  double ctrl_gain_n = 60.0;       // switching gain K
  double ctrl_phi_mps = 0.25;      // boundary layer half-width on s

  // [simulation]
  double cycle_s = 0.1;          // Execution-level cycle (10 Hz)
  int substeps = 10;             // integration sub-steps per cycle
  double tank_depth_m = 6.0;     // the tank bottom; depth is clamped to [0, tank_depth_m]

  // [detection]
  double depth_tolerance_m = 0.1;  // depth_reached: |z - z_d| < this ...
  double settle_rate_mps = 0.05;   // ... and |rate| < this
  double surface_depth_m = 0.15;   // surface_reached: depth <= this

  // [watchdog]
  double watchdog_s = 3.0;       // link silence after which the vehicle surfaces itself

  double total_mass_kg() const { return mass_kg + added_mass_kg; }
  // Largest total thrust both thrusters give at full health, N.
  double max_total_thrust_n() const { return 2.0 * thruster_max_n; }

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

}  // namespace strata::vehicle
