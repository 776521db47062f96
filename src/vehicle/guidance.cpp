#include "vehicle/guidance.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "vehicle/yaw.h"

namespace strata::vehicle {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

struct Line {
  double ux, uy, length;  // unit direction and length
};

Line line_of(const Guidance& g) {
  const double dx = g.x1_m - g.x0_m;
  const double dy = g.y1_m - g.y0_m;
  const double len = std::hypot(dx, dy);
  if (!(len > 0.0)) return {0.0, 1.0, 0.0};
  return {dx / len, dy / len, len};
}

// Along-track distance of (x, y) from the line's start.
double along_m(const Guidance& g, const Line& l, double x_m, double y_m) {
  return (x_m - g.x0_m) * l.ux + (y_m - g.y0_m) * l.uy;
}

}  // namespace

std::string_view to_string(GuidanceMode mode) {
  switch (mode) {
    case GuidanceMode::None: return "none";
    case GuidanceMode::Waypoint: return "waypoint";
    case GuidanceMode::Track: return "track";
    case GuidanceMode::Loiter: return "loiter";
    case GuidanceMode::Hold: return "hold";
  }
  return "?";
}

double bearing_deg(double dx, double dy) { return wrap_heading_deg(std::atan2(dx, dy) * kDegPerRad); }

double cross_track_m(const Guidance& g, double x_m, double y_m) {
  const Line l = line_of(g);
  if (l.length == 0.0) return 0.0;
  // Right of the direction (ux, uy) is (uy, -ux) in x east, y north.
  return (x_m - g.x0_m) * l.uy - (y_m - g.y0_m) * l.ux;
}

double guidance_heading_deg(const VehicleParams& p, const Guidance& g, const GuidanceInput& in) {
  double aim_x = g.x1_m;
  double aim_y = g.y1_m;
  if (g.mode == GuidanceMode::Track) {
    const Line l = line_of(g);
    const double s = along_m(g, l, in.x_m, in.y_m) + p.los_lookahead_m;
    if (l.length > 0.0 && s < l.length) {
      aim_x = g.x0_m + s * l.ux;
      aim_y = g.y0_m + s * l.uy;
    }
  } else if (g.mode == GuidanceMode::Loiter && g.radius_m > 0.0) {
    const double cx = in.x_m - g.x1_m;
    const double cy = in.y_m - g.y1_m;
    const double from_centre = std::hypot(cx, cy) > 1e-9 ? std::atan2(cx, cy) : 0.0;  // compass, rad
    const double ahead = from_centre + std::min(p.los_lookahead_m / g.radius_m, std::numbers::pi / 2.0);
    aim_x = g.x1_m + g.radius_m * std::sin(ahead);
    aim_y = g.y1_m + g.radius_m * std::cos(ahead);
  }
  const double dx = aim_x - in.x_m;
  const double dy = aim_y - in.y_m;
  const double dist = std::hypot(dx, dy);
  if (!(dist > 1e-9)) return bearing_deg(0.0, 1.0);
  const double lx = dx / dist;
  const double ly = dy / dist;
  // Crab: choose the water velocity w (|w| = speed) so that w + current lies
  // along the line of sight: cancel the current's component across it.
  const double across = in.current_x_mps * ly - in.current_y_mps * lx;  // right of the LOS
  if (in.speed_mps > std::abs(across) && in.speed_mps > 0.0) {
    const double along = std::sqrt(in.speed_mps * in.speed_mps - across * across);
    // w = along * l - across * r, with r = (ly, -lx) the right of the LOS.
    return bearing_deg(along * lx - across * ly, along * ly + across * lx);
  }
  return bearing_deg(dx, dy);
}

bool guidance_reached(const VehicleParams& p, const Guidance& g, double x_m, double y_m) {
  switch (g.mode) {
    case GuidanceMode::None: return false;
    case GuidanceMode::Waypoint:
    case GuidanceMode::Hold: return std::hypot(g.x1_m - x_m, g.y1_m - y_m) < p.waypoint_radius_m;
    case GuidanceMode::Loiter:
      return std::abs(std::hypot(g.x1_m - x_m, g.y1_m - y_m) - g.radius_m) < p.waypoint_radius_m;
    case GuidanceMode::Track: {
      const Line l = line_of(g);
      return along_m(g, l, x_m, y_m) > l.length - p.waypoint_radius_m;
    }
  }
  return false;
}

}  // namespace strata::vehicle
