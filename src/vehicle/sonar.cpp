#include "vehicle/sonar.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include "core/units.h"

namespace strata::vehicle {

using core::kRadPerDeg;

namespace {

// The beam is traced as kRays rays spread evenly over twice its (-3 dB)
// width, each weighted by a Gaussian beam pattern: 1 on the axis, 1/2 at
// half the width off it (-3 dB), 1/16 at the full width.
constexpr int kRays = 13;

double ray_offset_deg(const VehicleParams& p, int j) { return (2.0 * j / (kRays - 1) - 1.0) * p.sonar_beam_width_deg; }

struct BeamPattern {
  double weight[kRays];
  explicit BeamPattern(const VehicleParams& p) {
    double sum = 0.0;
    for (int j = 0; j < kRays; ++j) {
      const double u = 2.0 * ray_offset_deg(p, j) / p.sonar_beam_width_deg;
      weight[j] = std::exp2(-u * u);
      sum += weight[j];
    }
    for (double& w : weight) w /= sum;  // a wall filling the beam gives the full echo
  }
};

// The sonar's RNG stream: the scenario's seed through splitmix64 with a tag,
// so it is unrelated to the depth cell's stream (seeded with the seed itself).
std::uint64_t sonar_seed(std::uint64_t seed) {
  std::uint64_t z = seed ^ 0x534f4e4152ull;  // "SONAR"
  z += 0x9e3779b97f4a7c15ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

// Adds an echo of peak `amplitude` at range_m, Gaussian over the bins with a
// standard deviation of one bin.
void add_echo(std::vector<double>& level, double bin_m, double range_m, double amplitude) {
  const double centre = range_m / bin_m - 0.5;  // in bin-centre units
  const int n = static_cast<int>(level.size());
  const int lo = std::max(0, static_cast<int>(std::floor(centre)) - 3);
  const int hi = std::min(n - 1, static_cast<int>(std::ceil(centre)) + 3);
  for (int i = lo; i <= hi; ++i) {
    const double d = i - centre;
    level[static_cast<std::size_t>(i)] += amplitude * std::exp(-0.5 * d * d);
  }
}

}  // namespace

RayHit wall_hit(const VehicleParams& p, double x_m, double y_m, double dir_deg) {
  const double dx = std::sin(dir_deg * kRadPerDeg);
  const double dy = std::cos(dir_deg * kRadPerDeg);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const double tx = dx > 0.0 ? (p.tank_length_x_m - x_m) / dx : dx < 0.0 ? -x_m / dx : kInf;
  const double ty = dy > 0.0 ? (p.tank_width_y_m - y_m) / dy : dy < 0.0 ? -y_m / dy : kInf;
  if (tx < ty) return {std::max(tx, 0.0), std::abs(dx)};
  return {std::max(ty, 0.0), std::abs(dy)};
}

std::optional<RayHit> cylinder_hit(const Target& t, double x_m, double y_m, double dir_deg) {
  const double dx = std::sin(dir_deg * kRadPerDeg);
  const double dy = std::cos(dir_deg * kRadPerDeg);
  const double fx = x_m - t.x_m;
  const double fy = y_m - t.y_m;
  const double c = fx * fx + fy * fy - t.radius_m * t.radius_m;
  if (c <= 0.0) return std::nullopt;  // inside
  const double b = fx * dx + fy * dy;
  const double disc = b * b - c;
  if (disc < 0.0 || b >= 0.0) return std::nullopt;  // misses, or behind
  const double range = -b - std::sqrt(disc);
  const double nx = (fx + range * dx) / t.radius_m;
  const double ny = (fy + range * dy) / t.radius_m;
  return RayHit{range, std::clamp(-(nx * dx + ny * dy), 0.0, 1.0)};
}

Sonar::Sonar(const VehicleParams& p, std::uint64_t seed, std::optional<Target> target, bool tank_walls)
    : p_(p),
      target_(target),
      tank_walls_(tank_walls),
      rng_(sonar_seed(seed)),
      step_deg_(p.sonar_step_deg),
      max_step_(static_cast<int>(std::floor(p.sonar_sector_half_deg / p.sonar_step_deg + 1e-9))),
      substeps_per_ping_(std::max(1, static_cast<int>(std::lround(p.sonar_ping_period_s * p.substeps / p.cycle_s)))) {}

void Sonar::start() {
  if (on_) return;
  on_ = true;
  countdown_ = 1;
  window_.clear();
}

void Sonar::substep(double time_s, const Pose& pose) {
  if (!on_ || --countdown_ > 0) return;
  countdown_ = substeps_per_ping_;
  protocol::SonarPing ping = make_ping(time_s, bearing_deg(), pose);
  window_.push_back(shows_target(ping));
  while (window_.size() > static_cast<std::size_t>(period_pings())) window_.pop_front();
  if (buffer_.size() >= static_cast<std::size_t>(p_.sonar_buffer_pings)) {
    buffer_.pop_front();
    ++dropped_;
  }
  buffer_.push_back(std::move(ping));
  if (max_step_ > 0) {
    if (step_ + direction_ > max_step_ || step_ + direction_ < -max_step_) direction_ = -direction_;
    step_ += direction_;
  }
}

std::vector<protocol::SonarPing> Sonar::take_pings() {
  std::vector<protocol::SonarPing> out(std::make_move_iterator(buffer_.begin()),
                                       std::make_move_iterator(buffer_.end()));
  buffer_.clear();
  return out;
}

bool Sonar::target_detected() const {
  if (!on_) return false;
  return std::count(window_.begin(), window_.end(), true) >= p_.sonar_detect_min_pings;
}

protocol::SonarPing Sonar::make_ping(double time_s, double bearing_deg, const Pose& pose) {
  const auto n = static_cast<std::size_t>(p_.sonar_bins);
  const double bin_m = p_.sonar_range_m / static_cast<double>(n);
  std::vector<double> level(n, 0.0);
  static_assert(kRays > 1);
  const BeamPattern pattern(p_);
  for (int j = 0; j < kRays; ++j) {
    const double dir = pose.heading_deg + bearing_deg + ray_offset_deg(p_, j);
    const RayHit wall = this->wall(pose, dir);
    RayHit hit = wall;
    double echo = p_.sonar_wall_echo;
    const auto t = target_ ? cylinder_hit(*target_, pose.x_m, pose.y_m, dir) : std::nullopt;
    if (t && t->range_m < wall.range_m) {  // the wall behind is in its shadow
      hit = *t;
      echo = p_.sonar_target_echo;
    }
    if (std::isfinite(hit.range_m)) add_echo(level, bin_m, hit.range_m, echo * hit.cos_incidence * pattern.weight[j]);
  }
  protocol::SonarPing ping;
  ping.time_s = time_s;
  ping.seq = next_seq_++;
  ping.bearing_deg = static_cast<float>(bearing_deg);
  ping.heading_deg = static_cast<float>(pose.heading_deg);
  ping.x_m = static_cast<float>(pose.x_m);
  ping.y_m = static_cast<float>(pose.y_m);
  ping.range_m = static_cast<float>(p_.sonar_range_m);
  ping.bins.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double v = level[i] - p_.sonar_noise * std::log(uniform());
    ping.bins[i] = static_cast<std::uint8_t>(std::clamp(std::round(v), 0.0, 255.0));
  }
  return ping;
}

bool Sonar::shows_target(const protocol::SonarPing& ping) const {
  const Pose pose{ping.x_m, ping.y_m, ping.heading_deg};
  const double limit_m = nearest_wall_m(pose, ping.bearing_deg) - p_.sonar_detect_margin_m;
  const double bin_m = p_.sonar_range_m / static_cast<double>(ping.bins.size());
  for (std::size_t i = 0; i < ping.bins.size(); ++i) {
    if ((static_cast<double>(i) + 1.0) * bin_m > limit_m) break;
    if (ping.bins[i] >= p_.sonar_detect_threshold) return true;
  }
  return false;
}

RayHit Sonar::wall(const Pose& pose, double dir_deg) const {
  if (!tank_walls_) return {std::numeric_limits<double>::infinity(), 0.0};
  return wall_hit(p_, pose.x_m, pose.y_m, dir_deg);
}

// The nearest wall over the beam's rays: what the detector compares with.
double Sonar::nearest_wall_m(const Pose& pose, double bearing_deg) const {
  double nearest = std::numeric_limits<double>::infinity();
  for (int j = 0; j < kRays; ++j) {
    const double dir = pose.heading_deg + bearing_deg + ray_offset_deg(p_, j);
    nearest = std::min(nearest, wall(pose, dir).range_m);
  }
  return nearest;
}

// Uniform in (0, 1) from the top 53 bits: never 0, so log is finite.
double Sonar::uniform() { return (static_cast<double>(rng_() >> 11) + 0.5) * 0x1.0p-53; }

}  // namespace strata::vehicle
