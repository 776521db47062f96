#pragma once
// The mission data file (setpoints.toml) and the cursor that serves it to
// next_setpt_data and next_waypoint. The file holds [[setpoint]] tables,
// [[waypoint]] tables, or both (at least one of either):
//
//   [[setpoint]]
//   name = "working depth"   # optional
//   depth_m = 1.5            # positive down, 0 .. DataLimits::max_depth_m
//   timeout_s = 45           # above 0: the manoeuvre's time limit
//
//   [[waypoint]]             # open water: a plan from a planner, in order
//   name = "leg 1 start"     # optional
//   x_m = 0.0                # east, m, |x| <= 100 km (the catalogue's goto_xy range)
//   y_m = 100.0              # north, m, likewise
//
// Any other key, an empty list or a value of the wrong type is an error,
// located as "path:line:col: message". Setpoints and waypoints have cursors
// of their own.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"

namespace strata::tactical {

struct Setpoint {
  std::string name;  // "" when the file gives none
  double depth_m = 0;
  double timeout_s = 0;
  std::uint32_t line = 0;  // where its [[setpoint]] starts
};

struct Waypoint {
  std::string name;  // "" when the file gives none
  double x_m = 0;
  double y_m = 0;
  std::uint32_t line = 0;  // where its [[waypoint]] starts
};

inline constexpr double kMaxWaypointM = 100000.0;

struct DataLimits {
  // The deepest setpoint accepted. The default is tank_depth_m of
  // config/phoenix.toml (an estimate, not NPS data); the vehicle's parameters
  // are the authority, so a run passes the depth of its own tank.
  double max_depth_m = 6.0;
};

class MissionData {
 public:
  static core::Result<MissionData> load(const std::string& path, const DataLimits& limits = {});
  // The same from text; source_name labels the errors.
  static core::Result<MissionData> parse(std::string_view text, const std::string& source_name,
                                         const DataLimits& limits = {});

  const std::vector<Setpoint>& setpoints() const { return setpoints_; }
  const std::vector<Waypoint>& waypoints() const { return waypoints_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::vector<Setpoint> setpoints_;
  std::vector<Waypoint> waypoints_;
};

// Reads the setpoints in order, one per next_setpt_data call. Holds a
// reference: the MissionData must outlive the cursor. Single-threaded.
class DataCursor {
 public:
  explicit DataCursor(const MissionData& data) : data_(&data) {}

  // The next setpoint, which becomes current(). Past the last one: an
  // InvalidInput error ("mission data has 3 setpoints; next_setpt_data was
  // called a 4th time"); current() is then left as it was.
  core::Result<const Setpoint*> next();
  // The setpoint read by the last successful next(); nullptr before the first.
  const Setpoint* current() const;
  // How many setpoints next() has handed out (0 .. size).
  std::size_t position() const { return position_; }
  // The same for the waypoints, one per next_waypoint call ("mission data has
  // 2 waypoints; next_waypoint was called a 3rd time" past the last).
  core::Result<const Waypoint*> next_waypoint();
  const Waypoint* current_waypoint() const;
  std::size_t waypoint_position() const { return waypoint_position_; }
  const MissionData& data() const { return *data_; }

 private:
  const MissionData* data_;
  std::size_t position_ = 0;
  std::size_t calls_ = 0;
  std::size_t waypoint_position_ = 0;
  std::size_t waypoint_calls_ = 0;
};

// "1st", "2nd", "3rd", "4th", "11th", "21st", ...
std::string ordinal(std::size_t n);

}  // namespace strata::tactical
