#pragma once
// The simulated forward-looking scanning sonar (ST1000-like): one narrow
// beam on a mechanically stepped head, one bearing per ping, sweeping back
// and forth over a sector about the bow, and the vehicle's own target
// detector on its pings.
//
// Scan: bearings are whole steps k * sonar_step_deg from the bow, k in
// [-K, K] with K = floor(sonar_sector_half_deg / sonar_step_deg); the head
// starts at k = 0 moving to starboard and reverses at each end without
// repeating it (0, 1, ..., K, K-1, ..., -K, -K+1, ...). A full sweep, one end
// to the other, is 2K + 1 pings. The head stays where it is while stopped.
//
// Timing: substep() is called at the end of every integration sub-step
// (params.cycle_s / params.substeps); a started sonar pings at the first
// sub-step after start() and then every sonar_ping_period_s rounded to whole
// sub-steps (at least one), so pings come at sub-step resolution.
//
// Echoes, along the beam (the transducer is taken at the vehicle's (x, y);
// the tank's plan is a rectangle, the target a vertical cylinder, all 2-D):
// the beam is traced as 13 rays spread evenly over twice its -3 dB width,
// weighted by a Gaussian beam pattern (1/2 at half the width off the axis,
// 1/16 at the full width; the weights sum to 1). A ray returns from the first
// thing it meets: the target (sonar_target_echo) or else the wall
// (sonar_wall_echo), each times the cosine of the incidence angle, spread
// over the bins as a Gaussian with a standard deviation of one bin (so a
// wall met obliquely smears over more bins, weaker). A ray stopped by the
// target leaves the wall behind it in shadow. Nothing returns from beyond
// sonar_range_m; ranges are taken as TVG compensated (no spreading loss).
// Every bin gets background noise, an exponential deviate of mean
// sonar_noise, from the sonar's own RNG stream (seeded from the scenario's
// seed, separate from the depth cell's, one deviate per bin per ping), so a
// seed gives the same pings bit for bit.
// Intensities are rounded and clamped to 0..255.
//
// Detector: a ping shows a target when a bin at or above
// sonar_detect_threshold lies wholly at least sonar_detect_margin_m short of
// the nearest wall met by any of the beam's rays (the vehicle knows the tank
// and its own pose, taken from the ping); target_detected() is true while
// at least sonar_detect_min_pings of the pings of the last scan period (the
// head's way there and back, 4K pings) show one. One way (2K + 1 pings) is
// not enough: a bearing near the end of the sector is passed twice in quick
// succession and then not again for most of a period, so a window of one
// way can hold neither pass. The window is emptied by start().
//
// Pings wait in a buffer of sonar_buffer_pings until take_pings(); when it is
// full the oldest is dropped and counted (its seq is then missing).
// Not thread-safe; deterministic.
#include <algorithm>
#include <cstdint>
#include <deque>
#include <optional>
#include <random>
#include <vector>

#include "protocol/sonar_frame.h"
#include "vehicle/params.h"
#include "vehicle/scenario.h"

namespace strata::vehicle {

// Where the vehicle is and where its bow points.
struct Pose {
  double x_m = 0.0;
  double y_m = 0.0;
  double heading_deg = 0.0;
};

// Where a ray from (x_m, y_m) along compass direction dir_deg meets
// something: its range, and the cosine of the angle between the ray and the
// surface's normal there (1: head on).
struct RayHit {
  double range_m = 0.0;
  double cos_incidence = 0.0;
};

// The tank's wall, for a point inside the tank.
RayHit wall_hit(const VehicleParams& p, double x_m, double y_m, double dir_deg);
// The near side of the cylinder, or nullopt if the ray misses it (or starts
// inside it).
std::optional<RayHit> cylinder_hit(const Target& t, double x_m, double y_m, double dir_deg);

class Sonar {
 public:
  // tank_walls: the tank's plan bounds the water (the tank world); false in
  // open water, where nothing but a target returns an echo within range.
  Sonar(const VehicleParams& p, std::uint64_t seed, std::optional<Target> target, bool tank_walls = true);

  // Idempotent; start() empties the detector's window, the buffer stays.
  void start();
  void stop() { on_ = false; }
  bool on() const { return on_; }

  // One integration sub-step ended at time_s with the vehicle at pose: pings
  // if on and due.
  void substep(double time_s, const Pose& pose);

  // The pings made since the last call, oldest first.
  std::vector<protocol::SonarPing> take_pings();
  std::uint32_t pings() const { return next_seq_; }   // made so far (the next seq)
  std::uint64_t dropped() const { return dropped_; }  // lost to a full buffer
  bool target_detected() const;
  // The head's bearing from the bow for the next ping, deg.
  double bearing_deg() const { return step_ * step_deg_; }
  // Pings in a full sweep, one way.
  int sweep_pings() const { return 2 * max_step_ + 1; }
  // Pings in a scan period, there and back: the detector's window.
  int period_pings() const { return std::max(1, 4 * max_step_); }

  // The ping at this bearing and pose (draws its noise; no other effect).
  protocol::SonarPing make_ping(double time_s, double bearing_deg, const Pose& pose);
  // Does this ping show a return short of the wall (the detector's test)?
  bool shows_target(const protocol::SonarPing& ping) const;

 private:
  double uniform();
  // The wall along dir_deg: wall_hit in the tank; in open water none (an
  // infinite range, nothing returned).
  RayHit wall(const Pose& pose, double dir_deg) const;
  double nearest_wall_m(const Pose& pose, double bearing_deg) const;

  VehicleParams p_;
  std::optional<Target> target_;
  bool tank_walls_;
  std::mt19937_64 rng_;
  double step_deg_;
  int max_step_;  // K
  int substeps_per_ping_;
  bool on_ = false;
  int step_ = 0;       // the head's position, in steps from the bow
  int direction_ = 1;  // +1: to starboard
  int countdown_ = 1;  // sub-steps until the next ping
  std::uint32_t next_seq_ = 0;
  std::uint64_t dropped_ = 0;
  std::deque<protocol::SonarPing> buffer_;
  std::deque<bool> window_;  // detector: the last period_pings() pings
};

}  // namespace strata::vehicle
