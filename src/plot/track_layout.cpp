#include "plot/track_layout.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "plot/script_parts.h"

namespace strata::plot::layout {

using script::gp_string;
using script::kAbortColour;
using script::num;

namespace {

// The strip under the data holds one row of numbers with room above them
// for the leaders; it never takes more than kMaxStrip of a small panel.
constexpr double kStripChars = 2.0;
constexpr double kMaxStrip = 0.3;

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

std::vector<double> spread(const std::vector<double>& wanted, double width_px, double width) {
  const std::size_t n = wanted.size();
  std::vector<double> at(n);
  if (n == 0) return at;
  if (width_px * static_cast<double>(n) > width) {
    for (std::size_t i = 0; i < n; ++i) at[i] = width * (static_cast<double>(i) + 0.5) / static_cast<double>(n);
    return at;
  }
  const double lo = width_px / 2;
  const double hi = width - width_px / 2;
  // Pushed right past the one before, then back left from the end: each
  // moves only as far as it must, and the order is kept.
  for (std::size_t i = 0; i < n; ++i) {
    at[i] = std::clamp(wanted[i], lo, hi);
    if (i > 0) at[i] = std::max(at[i], at[i - 1] + width_px);
  }
  at[n - 1] = std::min(at[n - 1], hi);
  for (std::size_t i = n - 1; i-- > 0;) at[i] = std::min(at[i], at[i + 1] - width_px);
  return at;
}

double abort_strip(const MissionPlot& plot, const DepthPanel& panel) {
  if (plot.aborts.empty()) return 0.0;
  return std::min(kStripChars * kCharHeightPx / std::max(panel.height_px, 1.0), kMaxStrip);
}

std::string numbered_aborts(const MissionPlot& plot, const DepthPanel& panel) {
  std::vector<const AbortMark*> marks;
  marks.reserve(plot.aborts.size());
  for (const AbortMark& m : plot.aborts) marks.push_back(&m);
  std::stable_sort(marks.begin(), marks.end(),
                   [](const AbortMark* a, const AbortMark* b) { return a->time_s < b->time_s; });
  if (marks.empty()) return {};

  const double span = panel.last_s > panel.first_s ? panel.last_s - panel.first_s : 1.0;
  const double per_px = span / panel.width_px;
  std::vector<double> wanted;
  wanted.reserve(marks.size());
  for (const AbortMark* m : marks) wanted.push_back((m->time_s - panel.first_s) / per_px);
  const std::size_t digits = std::to_string(marks.size()).size();
  const auto at = spread(wanted, (static_cast<double>(digits) + 1) * kCharWidthPx, panel.width_px);
  const double strip = abort_strip(plot, panel);

  std::string s;
  for (std::size_t i = 0; i < marks.size(); ++i) {
    const AbortMark& m = *marks[i];
    const double number_s = panel.first_s + at[i] * per_px;
    s += fmt::format("set arrow from first {0}, graph {1} to first {0}, graph 1 nohead lc rgb '{2}' {3} front\n",
                     num(m.time_s), num(strip), kAbortColour, m.mission ? "dt 1 lw 2.5" : "dt 2 lw 1.5");
    if (std::abs(at[i] - wanted[i]) > 1.0) {
      s += fmt::format("set arrow from first {}, graph {} to first {}, graph {} nohead lc rgb '{}' lw 1 front\n",
                       num(m.time_s), num(strip), num(number_s), num(strip * 0.6), kAbortColour);
    }
    s += fmt::format("set label '{}' at first {}, graph {} center tc rgb '{}' front\n", i + 1, num(number_s),
                     num(strip * 0.35), kAbortColour);
  }

  // The legend: a column of numbers, a column of texts beside it, starting
  // a row under the key; rows are counted in characters from the top.
  const double number_x = 1.0;
  const double text_x = number_x + static_cast<double>(digits) + 1.0;
  const auto last_row = static_cast<std::size_t>(panel.height_px / kCharHeightPx);
  std::size_t row = panel.key_rows + 1;
  auto legend = [&](const std::string& text, double x) {
    s += fmt::format("set label {} at graph 1, graph 1 left offset {},{} tc rgb '{}' front\n", gp_string(text), num(x),
                     num(-static_cast<double>(row)), kAbortColour);
  };
  for (std::size_t i = 0; i < marks.size(); ++i) {
    const auto lines = script::wrapped(marks[i]->label, panel.wrap);
    const bool last = i + 1 == marks.size();
    // A row is kept for saying how many did not fit, unless none is left.
    if (row + lines.size() + (last ? 0 : 1) > last_row) {
      legend(fmt::format("and {} more: see the log", marks.size() - i), number_x);
      break;
    }
    legend(std::to_string(i + 1), number_x);
    for (const std::string& line : lines) {
      legend(line, text_x);
      ++row;
    }
  }
  return s;
}

}  // namespace strata::plot::layout
