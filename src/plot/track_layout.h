#pragma once
// The parts of the open-water plot's layout that depend on its data (pure;
// track_script.cpp writes them into the script):
//
// - the x-y panel's frame: ranges that hold everything drawn, widened on
//   the short side so that the panel, at one metre as long on both axes, is
//   never a thin strip, and one tick step for both axes, so that the tick
//   labels are far enough apart to be read;
// - the abort marks of the depth panel: each abort line ends at a strip kept
//   free of data at the bottom of the panel, where its number sits (numbers
//   pushed apart when their lines are close), and the texts are listed by
//   number in the right margin, under the key.
//
// Sizes in pixels are estimates from the terminal's size and the font's
// (kCharWidthPx, kCharHeightPx: gnuplot's default PNG font, the SVG's
// 'sans,11' is smaller), erring towards more room.
#include <cstddef>
#include <string>
#include <vector>

#include "plot/plot_log.h"

namespace strata::plot::layout {

inline constexpr double kCharWidthPx = 8.5;
inline constexpr double kCharHeightPx = 16.0;

// The x-y panel's box is kept between these heights for its width (in
// metres, which are as long on both axes), and has at most this many tick
// intervals along its longer side.
inline constexpr double kMinXyAspect = 0.75;
inline constexpr double kMaxXyAspect = 1.0 / kMinXyAspect;
inline constexpr int kMaxXyTicks = 8;

struct XyFrame {
  double x0 = 0.0;
  double x1 = 0.0;
  double y0 = 0.0;
  double y1 = 0.0;
  double step = 1.0;  // the tick step of both axes
};

// The frame of everything the x-y panel draws: the estimated and true
// tracks, the planned lines and waypoints, the fixes; padded by 5 % of its
// longer side (at least 1 m), then widened about its centre on the short
// side to an aspect (height / width) within [kMinXyAspect, kMaxXyAspect].
XyFrame xy_frame(const MissionPlot& plot);

// The smallest of 1, 2 and 5 times a power of ten that cuts `span` into at
// most `max_intervals` (>= 1) intervals; 1 for a span that is not positive
// or not finite.
double tick_step(double span, int max_intervals);

// Positions (pixels along an axis [0, width]) for marks `width_px` wide that
// want to be at `wanted` (ascending): as near as they can be, in the same
// order, each at least `width_px` from the next and all within [width_px / 2,
// width - width_px / 2]. When they cannot all fit they are spaced evenly
// across the axis, closer than width_px.
std::vector<double> spread(const std::vector<double>& wanted, double width_px, double width);

// What the abort marks of a depth panel need to know of it.
struct DepthPanel {
  double first_s = 0.0;  // the time axis's range
  double last_s = 1.0;
  double width_px = 1.0;   // the graph's size (inside the border)
  double height_px = 1.0;  // (an estimate: the margins are counted in characters)
  std::size_t key_rows = 1;
  std::size_t wrap = 30;  // characters of a legend line
};

// The part of the depth panel's height (graph units) kept free at its
// bottom for the abort numbers: 0 without aborts.
double abort_strip(const MissionPlot& plot, const DepthPanel& panel);

// The depth panel's abort lines (each from the top down to the strip), their
// numbers in the strip (by time, from 1), a short leader where a number
// had to move off its line, and the legend in the right margin: each
// abort's number and text, wrapped at panel.wrap, as many as fit in the
// panel's height, then how many more there are. gnuplot commands, one a
// line.
std::string numbered_aborts(const MissionPlot& plot, const DepthPanel& panel);

}  // namespace strata::plot::layout
