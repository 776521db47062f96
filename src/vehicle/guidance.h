#pragma once
// Line-of-sight guidance in the plan: the heading the heading law should
// hold to reach a waypoint or to follow a track line, from the estimated
// position (navigation.h), never the true one.
//
// - Waypoint (goto_xy): aim straight at the waypoint.
// - Track (track): aim at the point lookahead_m ahead of the vehicle's
//   projection on the line from (x0, y0) to (x1, y1); the vehicle converges
//   to the line and then runs along it. Past the end point it aims at the
//   end point.
// In both, the estimated current is allowed for: the heading is chosen so
// that water velocity plus current points along the line of sight (a crab
// angle), when the vehicle is fast enough to do so; otherwise it heads
// straight into the line of sight.
//
// - Loiter (loiter): aim at the point lookahead_m ahead, clockwise (seen
//   from above: the compass bearing from the centre grows), of the vehicle's
//   projection on the circle of radius_m about (x1, y1); from far off the
//   vehicle heads for the circle's near side, from inside it spirals out.
// - Hold (hold_position, and every waypoint or track once reached): aim at
//   the point (x1, y1); the Simulation drives toward it only while it is
//   off station (simulation_horizontal.cpp, the hold law).
//
// Reached: waypoint and hold, when the estimated distance is below
// radius_m; track, when the estimated position's projection is within
// radius_m of the end or past it; loiter, when the estimated distance from
// the centre is within radius_m of the circle. Pure functions over a value
// type.
#include <string_view>

#include "vehicle/params.h"

namespace strata::vehicle {

enum class GuidanceMode { None, Waypoint, Track, Loiter, Hold };

std::string_view to_string(GuidanceMode mode);

struct Guidance {
  GuidanceMode mode = GuidanceMode::None;
  double x0_m = 0.0, y0_m = 0.0;  // track: the start of the line
  double x1_m = 0.0, y1_m = 0.0;  // the waypoint, the end of the line, the circle's centre, the point held
  double radius_m = 0.0;          // loiter: the circle's radius

  bool operator==(const Guidance&) const = default;
};

struct GuidanceInput {
  double x_m = 0.0, y_m = 0.0;                      // estimated position
  double current_x_mps = 0.0, current_y_mps = 0.0;  // estimated current
  double speed_mps = 0.0;                           // water speed the vehicle will hold
};

// The compass heading to hold, [0, 360). mode must not be None.
double guidance_heading_deg(const VehicleParams& p, const Guidance& g, const GuidanceInput& in);
bool guidance_reached(const VehicleParams& p, const Guidance& g, double x_m, double y_m);
// Signed distance of (x_m, y_m) from the track line, m: positive to the
// right (starboard) of the line's direction. 0 for a line of zero length.
double cross_track_m(const Guidance& g, double x_m, double y_m);

// Compass heading (0 = +y, 90 = +x) of the vector (dx, dy), [0, 360).
double bearing_deg(double dx, double dy);

}  // namespace strata::vehicle
