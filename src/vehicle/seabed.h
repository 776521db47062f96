#pragma once
// The seabed under open water, as a scenario gives it: its depth below the
// surface at each point of the plan (x east, y north, m; params.h).
//
//   flat   depth_m everywhere
//   slope  depth_m at the origin, changing by slope_x per metre of x and
//          slope_y per metre of y (positive: deeper), never above the surface
//   grid   depths_m[j][i] at (x0_m + i * spacing_m, y0_m + j * spacing_m),
//          nx columns by ny rows, bilinear between nodes; outside the grid
//          the nearest edge holds
//
// Pure value type; depth_at() is cheap (a handful of flops) and total: every
// finite (x, y) gives a finite depth >= 0.
#include <cstddef>
#include <string_view>
#include <vector>

namespace strata::vehicle {

enum class SeabedKind { Flat, Slope, Grid };

std::string_view to_string(SeabedKind kind);

struct Seabed {
  SeabedKind kind = SeabedKind::Flat;
  double depth_m = 30.0;  // flat; slope: at (0, 0)
  double slope_x = 0.0;   // slope: depth change per metre of x (m/m)
  double slope_y = 0.0;
  double x0_m = 0.0;  // grid: the first node
  double y0_m = 0.0;
  double spacing_m = 1.0;
  std::size_t nx = 0;  // grid: columns (along x) and rows (along y)
  std::size_t ny = 0;
  std::vector<double> depths_m;  // grid: row-major, ny * nx, row j is y0_m + j * spacing_m

  // The seabed's depth below the surface at (x_m, y_m), m, >= 0.
  double depth_at(double x_m, double y_m) const;

  bool operator==(const Seabed&) const = default;
};

// Limits the scenario reader enforces (and tests name).
inline constexpr std::size_t kMaxGridNodes = 10000;  // nx * ny
inline constexpr double kMaxSeabedDepthM = 11000.0;

}  // namespace strata::vehicle
