#pragma once
// What the sonar saw, in tank coordinates (docs/sonar.md, "Detection"):
// one echo point per ping (its first strong return), then, over a window of
// points, the tank's walls as straight segments (sequential RANSAC with a
// least-squares refit) and a target: a compact cluster of points that lie on
// no wall. Pure functions; deterministic (the RANSAC samples come from a
// fixed-seed generator).
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "protocol/sonar_frame.h"

namespace strata::sonar {

// Where the vehicle is: tank metres, compass heading of the bow in degrees
// (0 = tank +y, 90 = tank +x, clockwise).
struct Pose {
  double x_m = 0.0;
  double y_m = 0.0;
  double heading_deg = 0.0;
};

struct EchoOptions {
  double min_range_m = 0.5;  // nearer bins are the transducer's ringing and the vehicle itself
  int min_intensity = 48;    // a bin is strong at or above max(min_intensity, median + margin)
  int margin = 40;           // above the ping's median bin (its noise level)
  int min_run_bins = 2;      // a return is this many strong bins in a row (speckle is one bin)
  int max_run_bins = 4;      // bins of the return averaged for its range
};

struct EchoPoint {
  double x_m = 0.0;  // tank coordinates
  double y_m = 0.0;
  double range_m = 0.0;      // from the vehicle, along the beam
  double max_range_m = 0.0;  // the ping's range
  std::uint32_t seq = 0;     // the ping's
};

// The ping's first strong return past min_range_m, or nullopt (open water,
// or a ping with no bins or no range).
std::optional<EchoPoint> find_echo(const protocol::SonarPing& ping, const EchoOptions& options = {});

struct DetectOptions {
  double wall_tolerance_m = 0.15;  // a point within this of a line is on it (RANSAC inlier)
  int wall_min_points = 10;        // fewer inliers: no wall
  double wall_min_length_m = 1.5;  // a shorter segment is no wall
  double wall_max_gap_m = 1.0;     // a larger gap along the line splits it into stretches; the wall is
                                   // the one with the most points, joined by neighbours of 3 points or
                                   // more across gaps up to 3 times this (a target's shadow on the wall)
  double wall_min_core_m = 0.8;    // and its main stretch at least this long (a target's face is shorter)
  int max_walls = 4;
  int ransac_samples = 300;             // point pairs tried per wall
  double on_wall_m = 0.3;               // points this near a wall's line are not target candidates
  double cluster_link_m = 0.5;          // single-linkage distance between a cluster's points
  double target_max_radius_m = 0.6;     // every point of a target within this of its centroid
  double target_range_margin_m = 0.5;   // echoes this near the ping's range are no target candidates
                                        // (where a wall leaves the range, its end looks compact)
  int target_min_pings = 4;             // distinct pings that saw it
  double target_min_across_deg = 55.0;  // a cluster longer than 0.2 m must lie across the line of sight,
                                        // its long axis at least this far from it (a target's face is
                                        // across the beam; the end of a wall seen obliquely runs along it)
  double target_edge_deg = 4.0;         // beside a target (this far past either end, seen from the vehicle) ...
  double target_step_m = 0.5;           // ... no echo within this of the range at that end: it stands out
                                        // from what is behind it (a wall running on into a corner does not)
};

// A wall: the segment its points span, and its distance from the vehicle
// (perpendicular, to the wall's line: a wall runs on past what was seen).
struct Wall {
  double x1_m = 0.0, y1_m = 0.0, x2_m = 0.0, y2_m = 0.0;
  double distance_m = 0.0;
  int points = 0;
};

// A target: the centroid of its echo points (they lie on its face toward the
// vehicle), its range and bearing from the vehicle (bearing from the bow,
// positive to starboard, as the sonar's), and how many pings saw it.
struct Target {
  double x_m = 0.0, y_m = 0.0;
  double range_m = 0.0;
  double bearing_deg = 0.0;
  int pings = 0;
  int points = 0;
};

struct Detection {
  std::vector<Wall> walls;       // most points first
  std::optional<Target> target;  // the cluster seen by the most pings
};

Detection detect(std::span<const EchoPoint> points, const Pose& vehicle, const DetectOptions& options = {});

// Degrees in (-180, 180].
double normalise_deg(double deg);

}  // namespace strata::sonar
