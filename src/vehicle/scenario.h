#pragma once
// A scenario: the seed of the simulation's noise and the faults to inject, at
// simulation times. Read from TOML:
//
//   seed = 42                      # required, integer >= 0
//   description = "..."            # optional, free text
//   [[fault]]
//   kind = "weak_thrusters"        # thrust limited to health * nominal from at_s on
//   at_s = 0.0
//   health = 0.1                   # fraction of nominal thrust, [0, 1]
//   [[fault]]
//   kind = "leak"                  # system_problem() is true from at_s on
//   at_s = 12.0
//   [[fault]]
//   kind = "sensor_dropout"        # the depth cell gives no reading for duration_s
//   at_s = 5.0
//   duration_s = 2.0
//   [[fault]]
//   kind = "link_loss"             # the link to the vehicle goes silent
//   at_s = 3.0
//   duration_s = 4.0               # ... for duration_s, or
//   forever = true                 # ... until the end of the run (exactly one of the two)
//   [vehicle]                      # optional, and each key in it
//   x_m = 6.0                      # where the vehicle hovers in the tank's plan, m, >= 0
//   y_m = 4.0                      # (unset: the tank's centre)
//   heading_deg = 0.0              # its compass heading at t = 0, [0, 360); default 0
//   [target]                       # optional: an object for the sonar to find,
//   x_m = 6.0                      # a vertical cylinder standing on the tank's floor:
//   y_m = 7.0                      # its axis, m, and
//   radius_m = 0.3                 # its radius, m, > 0 (all three keys required)
//
// Positions are in the tank's plan (params.h: the box [0, tank_length_x_m] x
// [0, tank_width_y_m]); the file cannot know the tank's size, so the
// Simulation checks that the vehicle is inside (it moves it in, with an
// event, if not). Unknown keys, unknown kinds, missing or out-of-range fields are errors with
// "path:line:col: message". The simulation applies weak_thrusters, leak and
// sensor_dropout itself; link_loss is only exposed (Scenario::link_lost,
// Simulation::link_lost) for the protocol server to act on.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"

namespace strata::vehicle {

enum class FaultKind { WeakThrusters, Leak, SensorDropout, LinkLoss };

std::string_view to_string(FaultKind kind);

struct Fault {
  FaultKind kind = FaultKind::Leak;
  double at_s = 0.0;                 // simulation time the fault starts
  double health = 1.0;               // WeakThrusters only: fraction of nominal thrust
  std::optional<double> duration_s;  // SensorDropout (always set), LinkLoss (unset = forever)

  bool operator==(const Fault&) const = default;
};

// A vertical cylinder in the tank, for the sonar: axis at (x_m, y_m).
struct Target {
  double x_m = 0.0;
  double y_m = 0.0;
  double radius_m = 0.0;

  bool operator==(const Target&) const = default;
};

struct Scenario {
  std::uint64_t seed = 1;
  std::string description;
  std::vector<Fault> faults;          // in file order
  std::optional<double> vehicle_x_m;  // unset: the tank's centre
  std::optional<double> vehicle_y_m;
  double vehicle_heading_deg = 0.0;  // compass, [0, 360)
  std::optional<Target> target;

  // No faults.
  static Scenario nominal(std::uint64_t seed = 1) {
    Scenario s;
    s.seed = seed;
    s.description = "nominal";
    return s;
  }

  // Is the link lost at time t_s (some link_loss fault with at_s <= t_s < end)?
  bool link_lost(double t_s) const;
  // The start of the first link loss, if the scenario has one.
  std::optional<double> link_lost_at() const;

  bool operator==(const Scenario&) const = default;
};

core::Result<Scenario> load_scenario(std::string_view path);
// From text in memory; path is used in messages only.
core::Result<Scenario> parse_scenario(std::string_view text, std::string_view path);

}  // namespace strata::vehicle
