#include "sonar/detect.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/units.h"

namespace strata::sonar {

using core::kRadPerDeg;

namespace {

// splitmix64: the same samples on every platform, so detection is
// reproducible (std:: distributions are not portable).
class Random {
 public:
  std::size_t below(std::size_t n) { return static_cast<std::size_t>(next() % n); }

 private:
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  std::uint64_t state_ = 0x5EED;
};

// A line as n . p = d, n a unit normal; u = the direction along it.
struct Line {
  double nx = 0.0, ny = 0.0, d = 0.0;
  double distance(const EchoPoint& p) const { return std::abs(nx * p.x_m + ny * p.y_m - d); }
  double along(const EchoPoint& p) const { return -ny * p.x_m + nx * p.y_m; }
};

// Total least squares: the line through the centroid along the principal axis.
Line fit_line(std::span<const EchoPoint> pts, const std::vector<std::size_t>& which) {
  double cx = 0.0, cy = 0.0;
  for (auto i : which) {
    cx += pts[i].x_m;
    cy += pts[i].y_m;
  }
  cx /= static_cast<double>(which.size());
  cy /= static_cast<double>(which.size());
  double sxx = 0.0, syy = 0.0, sxy = 0.0;
  for (auto i : which) {
    const double dx = pts[i].x_m - cx, dy = pts[i].y_m - cy;
    sxx += dx * dx;
    syy += dy * dy;
    sxy += dx * dy;
  }
  const double angle = 0.5 * std::atan2(2.0 * sxy, sxx - syy);  // of the principal axis
  Line line{-std::sin(angle), std::cos(angle), 0.0};
  line.d = line.nx * cx + line.ny * cy;
  return line;
}

std::vector<std::size_t> inliers(std::span<const EchoPoint> pts, const std::vector<std::size_t>& from, const Line& line,
                                 double tolerance) {
  std::vector<std::size_t> in;
  for (auto i : from) {
    if (line.distance(pts[i]) <= tolerance) in.push_back(i);
  }
  return in;
}

// A wall's points among a line's inliers: its core, the stretch with the
// most new points (not on a wall found before) and no gap over max_gap,
// joined by neighbouring stretches of 3 new points or more across gaps of
// up to 3 max_gap (the wall behind a target's shadow).
struct WallRun {
  std::vector<std::size_t> points;  // sorted along the line
  std::size_t core_new = 0;         // new points in the core
  double core_length_m = 0.0;
};

WallRun wall_run(std::span<const EchoPoint> pts, std::vector<std::size_t> in, const Line& line, double max_gap,
                 const std::vector<bool>& used) {
  WallRun out;
  if (in.empty()) return out;
  std::sort(in.begin(), in.end(), [&](auto a, auto b) { return line.along(pts[a]) < line.along(pts[b]); });
  struct Stretch {
    std::size_t begin, end, fresh;
  };
  std::vector<Stretch> stretches;
  std::size_t begin = 0;
  for (std::size_t k = 1; k <= in.size(); ++k) {
    if (k == in.size() || line.along(pts[in[k]]) - line.along(pts[in[k - 1]]) > max_gap) {
      std::size_t fresh = 0;
      for (std::size_t j = begin; j < k; ++j) fresh += used[in[j]] ? 0 : 1;
      stretches.push_back({begin, k, fresh});
      begin = k;
    }
  }
  std::size_t best = 0;
  for (std::size_t s = 1; s < stretches.size(); ++s) {
    if (stretches[s].fresh > stretches[best].fresh) best = s;
  }
  auto at = [&](std::size_t k) { return line.along(pts[in[k]]); };
  out.core_new = stretches[best].fresh;
  out.core_length_m = at(stretches[best].end - 1) - at(stretches[best].begin);
  auto joins = [&](std::size_t s, std::size_t towards) {
    const double gap = s < towards ? at(stretches[towards].begin) - at(stretches[s].end - 1)
                                   : at(stretches[s].begin) - at(stretches[towards].end - 1);
    return stretches[s].fresh >= 3 && gap <= 3.0 * max_gap;
  };
  std::size_t first = best, last = best;
  while (first > 0 && joins(first - 1, first)) --first;
  while (last + 1 < stretches.size() && joins(last + 1, last)) ++last;
  out.points.assign(in.begin() + static_cast<std::ptrdiff_t>(stretches[first].begin),
                    in.begin() + static_cast<std::ptrdiff_t>(stretches[last].end));
  return out;
}

std::optional<Line> ransac(std::span<const EchoPoint> pts, const std::vector<std::size_t>& left, const DetectOptions& o,
                           Random& random) {
  std::size_t best = 0;
  Line best_line;
  for (int s = 0; s < o.ransac_samples; ++s) {
    const auto& a = pts[left[random.below(left.size())]];
    const auto& b = pts[left[random.below(left.size())]];
    const double dx = b.x_m - a.x_m, dy = b.y_m - a.y_m;
    const double length = std::hypot(dx, dy);
    if (length < 0.3) continue;  // too near each other to give a direction
    Line line{-dy / length, dx / length, 0.0};
    line.d = line.nx * a.x_m + line.ny * a.y_m;
    std::size_t count = 0;
    for (auto i : left) count += line.distance(pts[i]) <= o.wall_tolerance_m ? 1 : 0;
    if (count > best) best = count, best_line = line;
  }
  if (best < static_cast<std::size_t>(o.wall_min_points)) return std::nullopt;
  return best_line;
}

// Does the cluster (longer than 0.2 m) run along the line of sight rather
// than across it?
bool lies_along_the_beam(std::span<const EchoPoint> pts, const std::vector<std::size_t>& left,
                         const std::vector<std::size_t>& members, double cx, double cy, const Pose& vehicle,
                         const DetectOptions& o) {
  double sxx = 0.0, syy = 0.0, sxy = 0.0;
  for (auto m : members) {
    const double dx = pts[left[m]].x_m - cx, dy = pts[left[m]].y_m - cy;
    sxx += dx * dx;
    syy += dy * dy;
    sxy += dx * dy;
  }
  const double n = static_cast<double>(members.size());
  const double spread =
      (sxx + syy) / (2.0 * n) + std::sqrt(std::pow((sxx - syy) / (2.0 * n), 2) + std::pow(sxy / n, 2));
  if (std::sqrt(spread) * 2.0 < 0.2) return false;  // too short to have a direction
  const double axis = 0.5 * std::atan2(2.0 * sxy, sxx - syy);
  const double sight = std::atan2(cy - vehicle.y_m, cx - vehicle.x_m);
  return std::abs(std::cos(axis - sight)) > std::cos(o.target_min_across_deg * kRadPerDeg);
}

// Is there a step in range at both ends of the cluster, seen from the
// vehicle: do the echoes just beside it come from farther away (or nearer),
// not from a surface that runs on from it?
bool stands_out(std::span<const EchoPoint> pts, const std::vector<std::size_t>& left,
                const std::vector<std::size_t>& members, double cx, double cy, const Pose& vehicle,
                const DetectOptions& o) {
  const double centre_deg = std::atan2(cx - vehicle.x_m, cy - vehicle.y_m) / kRadPerDeg;
  auto polar = [&](const EchoPoint& p) {
    return std::pair{normalise_deg(std::atan2(p.x_m - vehicle.x_m, p.y_m - vehicle.y_m) / kRadPerDeg - centre_deg),
                     std::hypot(p.x_m - vehicle.x_m, p.y_m - vehicle.y_m)};
  };
  std::vector<bool> member(pts.size(), false);
  double lo_deg = 1e9, hi_deg = -1e9, lo_range = 0.0, hi_range = 0.0;
  for (auto m : members) {
    member[left[m]] = true;
    const auto [deg, range] = polar(pts[left[m]]);
    if (deg < lo_deg) lo_deg = deg, lo_range = range;
    if (deg > hi_deg) hi_deg = deg, hi_range = range;
  }
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (member[i]) continue;
    const auto [deg, range] = polar(pts[i]);
    if (deg < lo_deg && deg >= lo_deg - o.target_edge_deg && std::abs(range - lo_range) < o.target_step_m) return false;
    if (deg > hi_deg && deg <= hi_deg + o.target_edge_deg && std::abs(range - hi_range) < o.target_step_m) return false;
  }
  return true;
}

std::optional<Target> find_target(std::span<const EchoPoint> pts, const std::vector<std::size_t>& left,
                                  const Pose& vehicle, const DetectOptions& o) {
  std::vector<int> cluster_of(left.size(), -1);
  std::optional<Target> best;
  int clusters = 0;
  for (std::size_t start = 0; start < left.size(); ++start) {
    if (cluster_of[start] >= 0) continue;
    // Single linkage: grow the cluster breadth first.
    std::vector<std::size_t> members{start};
    cluster_of[start] = clusters;
    for (std::size_t m = 0; m < members.size(); ++m) {
      const auto& p = pts[left[members[m]]];
      for (std::size_t k = 0; k < left.size(); ++k) {
        if (cluster_of[k] >= 0) continue;
        if (std::hypot(pts[left[k]].x_m - p.x_m, pts[left[k]].y_m - p.y_m) <= o.cluster_link_m) {
          cluster_of[k] = clusters;
          members.push_back(k);
        }
      }
    }
    ++clusters;
    double cx = 0.0, cy = 0.0;
    std::vector<std::uint32_t> seqs;
    for (auto m : members) {
      cx += pts[left[m]].x_m;
      cy += pts[left[m]].y_m;
      seqs.push_back(pts[left[m]].seq);
    }
    cx /= static_cast<double>(members.size());
    cy /= static_cast<double>(members.size());
    std::sort(seqs.begin(), seqs.end());
    const int pings = static_cast<int>(std::unique(seqs.begin(), seqs.end()) - seqs.begin());
    double radius = 0.0;
    for (auto m : members) radius = std::max(radius, std::hypot(pts[left[m]].x_m - cx, pts[left[m]].y_m - cy));
    if (radius > o.target_max_radius_m || pings < o.target_min_pings) continue;
    if (lies_along_the_beam(pts, left, members, cx, cy, vehicle, o)) continue;
    if (!stands_out(pts, left, members, cx, cy, vehicle, o)) continue;
    Target t;
    t.x_m = cx;
    t.y_m = cy;
    t.range_m = std::hypot(cx - vehicle.x_m, cy - vehicle.y_m);
    t.bearing_deg = normalise_deg(std::atan2(cx - vehicle.x_m, cy - vehicle.y_m) / kRadPerDeg - vehicle.heading_deg);
    t.pings = pings;
    t.points = static_cast<int>(members.size());
    if (!best || t.pings > best->pings || (t.pings == best->pings && t.range_m < best->range_m)) best = t;
  }
  return best;
}

}  // namespace

double normalise_deg(double deg) {
  double r = std::fmod(deg, 360.0);
  if (r <= -180.0) r += 360.0;
  if (r > 180.0) r -= 360.0;
  return r;
}

std::optional<EchoPoint> find_echo(const protocol::SonarPing& ping, const EchoOptions& o) {
  const std::size_t n = ping.bins.size();
  if (n == 0 || !(ping.range_m > 0.0f) || !std::isfinite(ping.range_m)) return std::nullopt;
  const double bin_m = static_cast<double>(ping.range_m) / static_cast<double>(n);
  // The median bin is the ping's noise level: most of a beam is open water.
  std::array<int, 256> histogram{};
  for (auto v : ping.bins) ++histogram[v];
  int median = 0;
  for (std::size_t seen = 0; median < 256; ++median) {
    seen += static_cast<std::size_t>(histogram[static_cast<std::size_t>(median)]);
    if (seen * 2 >= n) break;
  }
  const int threshold = std::max(o.min_intensity, median + o.margin);
  auto first = static_cast<std::size_t>(std::ceil(o.min_range_m / bin_m));
  const auto min_run = static_cast<std::size_t>(std::max(o.min_run_bins, 1));
  for (std::size_t i = first; i < n; ++i) {
    if (ping.bins[i] < threshold) continue;
    std::size_t end = i;
    while (end < n && ping.bins[end] >= threshold) ++end;
    if (end - i < min_run) {
      i = end;
      continue;
    }
    // The return's range: the intensity-weighted centre of its first bins.
    double sum = 0.0, weighted = 0.0;
    for (std::size_t j = i; j < end && j < i + static_cast<std::size_t>(o.max_run_bins); ++j) {
      sum += ping.bins[j];
      weighted += ping.bins[j] * (static_cast<double>(j) + 0.5);
    }
    EchoPoint e;
    e.range_m = weighted / sum * bin_m;
    const double theta = (static_cast<double>(ping.heading_deg) + ping.bearing_deg) * kRadPerDeg;
    e.x_m = ping.x_m + e.range_m * std::sin(theta);
    e.y_m = ping.y_m + e.range_m * std::cos(theta);
    e.seq = ping.seq;
    e.max_range_m = ping.range_m;
    return e;
  }
  return std::nullopt;
}

Detection detect(std::span<const EchoPoint> pts, const Pose& vehicle, const DetectOptions& o) {
  Detection out;
  std::vector<std::size_t> all(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) all[i] = i;
  std::vector<std::size_t> left = all;  // near no wall's line: target candidates
  // Not sampled again: points of a wall found, and inliers of a line that made no wall.
  std::vector<bool> used(pts.size(), false);
  std::vector<Line> lines;
  Random random;
  const auto min_points = static_cast<std::size_t>(o.wall_min_points);
  for (int attempt = 0; attempt < 3 * o.max_walls && static_cast<int>(out.walls.size()) < o.max_walls; ++attempt) {
    std::vector<std::size_t> candidates;
    for (auto i : all) {
      if (!used[i]) candidates.push_back(i);
    }
    if (candidates.size() < min_points) break;
    auto rough = ransac(pts, candidates, o, random);
    if (!rough) break;
    // Refit to the inliers among all points (a corner's points are on two
    // walls), keep the longest stretch without a gap, refit to that: points
    // in a line across open water (a target's face, stray echoes) make no wall.
    Line line = fit_line(pts, inliers(pts, all, *rough, o.wall_tolerance_m));
    const WallRun found = wall_run(pts, inliers(pts, all, line, o.wall_tolerance_m), line, o.wall_max_gap_m, used);
    const std::vector<std::size_t>& run = found.points;
    double t1 = std::numeric_limits<double>::infinity(), t2 = -t1;
    if (found.core_new >= min_points && found.core_length_m >= o.wall_min_core_m) {
      line = fit_line(pts, run);
      for (auto i : run) {
        t1 = std::min(t1, line.along(pts[i]));
        t2 = std::max(t2, line.along(pts[i]));
      }
    }
    if (!(t2 - t1 >= o.wall_min_length_m)) {
      for (auto i : inliers(pts, candidates, *rough, o.wall_tolerance_m)) used[i] = true;
      continue;
    }
    for (auto i : run) used[i] = true;
    // A wall seen in two stretches (a target's shadow between them) is one.
    bool merged = false;
    for (std::size_t k = 0; k < lines.size() && !merged; ++k) {
      const Line& same = lines[k];
      if (std::abs(same.nx * line.nx + same.ny * line.ny) < std::cos(5.0 * kRadPerDeg)) continue;
      if (same.distance(pts[run[run.size() / 2]]) > 2.0 * o.wall_tolerance_m) continue;
      Wall& w = out.walls[k];
      double a1 = same.along(EchoPoint{w.x1_m, w.y1_m}), a2 = same.along(EchoPoint{w.x2_m, w.y2_m});
      for (auto i : run) {
        a1 = std::min(a1, same.along(pts[i]));
        a2 = std::max(a2, same.along(pts[i]));
      }
      w.x1_m = same.d * same.nx - a1 * same.ny;
      w.y1_m = same.d * same.ny + a1 * same.nx;
      w.x2_m = same.d * same.nx - a2 * same.ny;
      w.y2_m = same.d * same.ny + a2 * same.nx;
      w.points += static_cast<int>(run.size());
      merged = true;
    }
    if (!merged) {
      Wall wall;
      // The point of the line at `t` along it: d * n + t * u, u = (-ny, nx).
      wall.x1_m = line.d * line.nx - t1 * line.ny;
      wall.y1_m = line.d * line.ny + t1 * line.nx;
      wall.x2_m = line.d * line.nx - t2 * line.ny;
      wall.y2_m = line.d * line.ny + t2 * line.nx;
      wall.distance_m = std::abs(line.nx * vehicle.x_m + line.ny * vehicle.y_m - line.d);
      wall.points = static_cast<int>(run.size());
      out.walls.push_back(wall);
      lines.push_back(line);
    }
    std::erase_if(left, [&](std::size_t i) { return line.distance(pts[i]) <= o.on_wall_m; });
  }
  std::stable_sort(out.walls.begin(), out.walls.end(),
                   [](const Wall& a, const Wall& b) { return a.points > b.points; });
  std::erase_if(left, [&](std::size_t i) { return pts[i].range_m > pts[i].max_range_m - o.target_range_margin_m; });
  out.target = find_target(pts, left, vehicle, o);
  return out;
}

}  // namespace strata::sonar
