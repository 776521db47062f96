#pragma once
// What the wire function `start_rows X Y HEADING LENGTH SPACING COUNT`
// means (docs/protocol.md): the rows of a lawnmower pattern. Both ends of
// the primitive use this one definition: the simulated vehicle
// (vehicle/simulation.h) and the IMC link (tactical/imc_link.h), which
// keeps the pattern itself.
//
// Row i (0-based) lies on the line that starts at (x, y) shifted
// i * spacing to the right (starboard) of `heading` (negative spacing: to
// port) and runs `length` m along `heading` (compass: 0 = +y north, 90 = +x
// east). Even rows are run along `heading`, odd rows back the other way
// (boustrophedon), so each row starts near where the last one ended.
// Pure; header only.
#include <cmath>
#include <numbers>
#include <optional>
#include <string>

#include <fmt/format.h>

namespace strata::protocol {

inline constexpr int kMaxRows = 1000;
inline constexpr double kMaxRowLengthM = 20000.0;  // a row is one leg: the vehicle's longest

struct RowPattern {
  double x_m = 0.0, y_m = 0.0;  // the first row's start
  double heading_deg = 0.0;     // the first row's direction, compass
  double length_m = 0.0;        // every row's length, > 0
  double spacing_m = 0.0;       // between rows, + starboard, - port
  int count = 0;                // 1 to kMaxRows

  bool operator==(const RowPattern&) const = default;
};

// One row, in the order it is run: from (x0, y0) to (x1, y1).
struct Row {
  double x0_m = 0.0, y0_m = 0.0;
  double x1_m = 0.0, y1_m = 0.0;

  bool operator==(const Row&) const = default;
};

// The pattern of start_rows' six numbers, or why they make none.
inline std::optional<RowPattern> make_row_pattern(double x_m, double y_m, double heading_deg, double length_m,
                                                  double spacing_m, double count, std::string* why) {
  auto no = [&](std::string text) {
    if (why) *why = std::move(text);
    return std::nullopt;
  };
  if (!std::isfinite(x_m) || !std::isfinite(y_m)) return no("the first row's start must be finite numbers");
  if (!std::isfinite(heading_deg) || heading_deg < 0.0 || heading_deg > 360.0) {
    return no(fmt::format("rows heading {} deg outside 0 to 360 deg", heading_deg));
  }
  if (!std::isfinite(length_m) || length_m <= 0.0 || length_m > kMaxRowLengthM) {
    return no(fmt::format("row length {} m outside (0, {}] m", length_m, kMaxRowLengthM));
  }
  if (!std::isfinite(spacing_m) || std::abs(spacing_m) > kMaxRowLengthM) {
    return no(fmt::format("row spacing {} m outside -{} to {} m", spacing_m, kMaxRowLengthM, kMaxRowLengthM));
  }
  if (!std::isfinite(count) || count != std::floor(count) || count < 1 || count > kMaxRows) {
    return no(fmt::format("row count {} is not a whole number from 1 to {}", count, kMaxRows));
  }
  return RowPattern{x_m, y_m, heading_deg == 360.0 ? 0.0 : heading_deg, length_m, spacing_m, static_cast<int>(count)};
}

// Row i of p, 0 <= i < p.count.
inline Row row_of(const RowPattern& p, int i) {
  const double h = p.heading_deg * std::numbers::pi / 180.0;
  const double ux = std::sin(h), uy = std::cos(h);  // along the heading
  const double rx = uy, ry = -ux;                   // its right (starboard)
  const double sx = p.x_m + i * p.spacing_m * rx;
  const double sy = p.y_m + i * p.spacing_m * ry;
  const double ex = sx + p.length_m * ux;
  const double ey = sy + p.length_m * uy;
  if (i % 2 == 0) return {sx, sy, ex, ey};
  return {ex, ey, sx, sy};
}

}  // namespace strata::protocol
