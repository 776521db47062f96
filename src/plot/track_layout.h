#pragma once
// The parts of the open-water plot's layout that depend on its data (pure;
// track_script.cpp writes them into the script):
//
// - the x-y panel's frame: ranges that hold everything drawn, widened on
//   the short side so that the panel, at one metre as long on both axes, is
//   never a thin strip, and one tick step for both axes, so that the tick
//   labels are far enough apart to be read.
#include "plot/plot_log.h"

namespace strata::plot::layout {

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

}  // namespace strata::plot::layout
