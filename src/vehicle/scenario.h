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
//   [[fault]]
//   kind = "compass_bias"          # the compass reads bias_deg more than the truth from
//   at_s = 0.0                     # at_s on: the heading law and dead reckoning use it
//   bias_deg = 10.0                # [-180, 180]
//   [[fault]]
//   kind = "altimeter_dead"        # the altimeter gives no reading from at_s on
//   at_s = 30.0
//   [[fault]]
//   kind = "no_gps"                # no GPS fix from at_s on (the receiver is dead)
//   at_s = 0.0
//   [world]                        # optional: where the vehicle is
//   kind = "open_water"            # "tank" (the default: the paper's test tank) or
//                                  # "open_water": no walls, a seabed, GPS, a current
//   current_x_mps = 0.0            # open water: the water current toward +x (east) and
//   current_y_mps = 0.2            # +y (north), m/s; |current| <= 5 (stronger than the
//                                  # vehicle's top speed is allowed: it is just a current)
//   [seabed]                       # open water only (the tank has its floor); default flat 30 m
//   kind = "flat"                  # flat | slope | grid (seabed.h)
//   depth_m = 30.0                 # flat: everywhere; slope: at (0, 0); (0, 11000] m
//   slope_x = 0.05                 # slope only: depth change per m of x, and of y,
//   slope_y = 0.0                  # |slope| <= 10
//   # grid only: x0_m, y0_m (the first node), spacing_m > 0, nx, ny >= 2 and
//   # depths_m = [[...], ...]: ny rows (along y) of nx depths (along x), at most
//   # 10000 nodes; a row of the wrong length is an error at that row
//   [vehicle]                      # optional, and each key in it
//   x_m = 6.0                      # where the vehicle starts in the tank's plan, m, >= 0
//   y_m = 4.0                      # (unset: the tank's centre)
//   heading_deg = 0.0              # its compass heading at t = 0, [0, 360); default 0
//   [target]                       # optional: an object for the sonar to find,
//   x_m = 6.0                      # a vertical cylinder standing on the tank's floor:
//   y_m = 7.0                      # its axis, m, and
//   radius_m = 0.3                 # its radius, m, > 0 (all three keys required)
//
// Tank (the default): positions are in the tank's plan (params.h: the box
// [0, tank_length_x_m] x [0, tank_width_y_m]); the file cannot know the
// tank's size, so the Simulation checks that the vehicle is inside (it moves
// it in, with an event, if not), and keeps it inside when it moves. There is
// no GPS under a roof: the position estimate is the truth (the tank's own
// positioning), and the altimeter sees the tank's floor.
// Open water: x is east and y north in metres from the scenario's origin;
// vehicle.x_m and y_m may be negative (|x|, |y| <= 100 km), and start the
// vehicle there (default: the origin). The launch position is known to
// navigation.initial_sd_m (params.h); GPS fixes at the surface refine it.
// The forward-looking sonar sees no walls in open water (only a target, if
// the scenario has one, within its range). Unknown keys, unknown kinds, missing or out-of-range fields are errors with
// "path:line:col: message". The simulation applies weak_thrusters, leak and
// sensor_dropout itself; link_loss is only exposed (Scenario::link_lost,
// Simulation::link_lost) for the protocol server to act on.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"
#include "vehicle/seabed.h"

namespace strata::vehicle {

enum class FaultKind { WeakThrusters, Leak, SensorDropout, LinkLoss, CompassBias, AltimeterDead, NoGps };

std::string_view to_string(FaultKind kind);

struct Fault {
  FaultKind kind = FaultKind::Leak;
  double at_s = 0.0;                 // simulation time the fault starts
  double health = 1.0;               // WeakThrusters only: fraction of nominal thrust
  std::optional<double> duration_s;  // SensorDropout (always set), LinkLoss (unset = forever)
  double bias_deg = 0.0;             // CompassBias only: compass reading - true heading

  bool operator==(const Fault&) const = default;
};

// A vertical cylinder in the tank, for the sonar: axis at (x_m, y_m).
struct Target {
  double x_m = 0.0;
  double y_m = 0.0;
  double radius_m = 0.0;

  bool operator==(const Target&) const = default;
};

// Where the vehicle is: the paper's tank, or open water with a current.
struct World {
  bool open_water = false;
  double current_x_mps = 0.0;  // open water: the current toward +x (east)
  double current_y_mps = 0.0;  // ... and toward +y (north)

  bool operator==(const World&) const = default;
};

// Limits the scenario reader enforces.
inline constexpr double kMaxCurrentMps = 5.0;
inline constexpr double kMaxPlanM = 100000.0;

struct Scenario {
  std::uint64_t seed = 1;
  std::string description;
  std::vector<Fault> faults;          // in file order
  std::optional<double> vehicle_x_m;  // unset: the tank's centre (open water: the origin)
  std::optional<double> vehicle_y_m;
  double vehicle_heading_deg = 0.0;  // compass, [0, 360)
  std::optional<Target> target;
  World world;
  Seabed seabed;  // open water only

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
// A scenario file read for its world (a campaign's `world`): as
// parse_scenario, but a missing seed is 0.
core::Result<Scenario> parse_world_scenario(std::string_view text, std::string_view path);

}  // namespace strata::vehicle
