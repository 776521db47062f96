#include "plot/track_layout.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace strata::plot::layout {

namespace {

// Widens [lo, hi] about its centre to `size`, when it is narrower.
void widen(double& lo, double& hi, double size) {
  if (hi - lo >= size) return;
  const double centre = (lo + hi) / 2;
  lo = centre - size / 2;
  hi = centre + size / 2;
}

}  // namespace

XyFrame xy_frame(const MissionPlot& plot) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  XyFrame f{kInf, -kInf, kInf, -kInf, 1.0};
  auto take = [&f](const Point& p) {
    f.x0 = std::min(f.x0, p.x_m);
    f.x1 = std::max(f.x1, p.x_m);
    f.y0 = std::min(f.y0, p.y_m);
    f.y1 = std::max(f.y1, p.y_m);
  };
  for (const Point& p : plot.estimated.at) take(p);
  for (const Point& p : plot.truth.at) take(p);
  for (const PlannedLeg& leg : plot.plan) {
    take(leg.to);
    if (leg.from_known) take(leg.from);
  }
  for (const Fix& fix : plot.fixes) take(fix.at);
  if (f.x0 > f.x1) f = {0.0, 0.0, 0.0, 0.0, 1.0};  // nothing drawn: a frame about the origin

  const double pad = std::max(0.05 * std::max(f.x1 - f.x0, f.y1 - f.y0), 1.0);
  f.x0 -= pad;
  f.x1 += pad;
  f.y0 -= pad;
  f.y1 += pad;
  // With equal scales the box has the data's shape: a straight leg would
  // be a strip a few pixels high, its y tick labels on top of each other.
  widen(f.y0, f.y1, kMinXyAspect * (f.x1 - f.x0));
  widen(f.x0, f.x1, (f.y1 - f.y0) / kMaxXyAspect);
  // One step on both axes: the grid is of squares, and the longer side,
  // which has the most ticks, has no more than kMaxXyTicks.
  f.step = tick_step(std::max(f.x1 - f.x0, f.y1 - f.y0), kMaxXyTicks);
  return f;
}

double tick_step(double span, int max_intervals) {
  if (!(span > 0) || !std::isfinite(span) || max_intervals < 1) return 1.0;
  const double least = span / max_intervals;
  const double power = std::pow(10.0, std::floor(std::log10(least)));
  for (double m : {1.0, 2.0, 5.0}) {
    // A hair of slack: 250 / 5 is 50 however log10 rounded.
    if (m * power >= least * (1 - 1e-9)) return m * power;
  }
  return 10 * power;
}

}  // namespace strata::plot::layout
