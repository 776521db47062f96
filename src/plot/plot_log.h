#pragma once
// A mission log (JSON Lines, tactical/mission_log.h) read into what a plot of
// the run shows: telemetry series against simulated time, the mission's
// phases as bands, and the aborts. Pure: no files are written, nothing runs.
#include <cstddef>
#include <cstdint>
#include <istream>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"

namespace strata::plot {

// Samples of one telemetry field, in log order; only the telemetry lines
// that carry the field contribute.
struct Series {
  std::vector<double> time_s;
  std::vector<double> value;

  std::size_t size() const { return time_s.size(); }
  bool empty() const { return time_s.empty(); }
};

// One phase instance, from its phase_start to its phase_end. depth 1 is a
// phase started by the mission's global net (depth 0, which is not kept);
// 2 and more are phases started by phases.
struct PhaseBand {
  std::uint64_t instance = 0;
  std::string net;
  int depth = 1;
  double start_s = 0.0;
  double end_s = 0.0;  // the log's last time when the phase never ended
  std::string result;  // "completed", "aborted", ...; "" when it never ended
  std::string exit;    // the exit place it ended through
  bool ended = false;
};

// A position in the horizontal plane: x east, y north, metres.
struct Point {
  double x_m = 0.0;
  double y_m = 0.0;
};

// Positions in log order; only telemetry lines carrying both coordinates of
// a pair, each within kMaxCoordinate_m, contribute.
struct Path {
  std::vector<double> time_s;
  std::vector<Point> at;

  std::size_t size() const { return time_s.size(); }
  bool empty() const { return time_s.empty(); }
};

// What the guidance was told to follow: a `track` line from `from` to `to`,
// or a `goto_xy` (and next_waypoint, sent as goto_xy) to `to`, from the
// estimated position when it was accepted (`from_known` false when no
// estimate came before). Only calls the vehicle accepted (reply 1).
struct PlannedLeg {
  double time_s = 0.0;  // of the request
  bool track = false;   // a track line, not a goto_xy
  bool from_known = true;
  Point from;
  Point to;
};

// A GPS fix the vehicle accepted (gps_fix answered 1), drawn where the
// estimate stood at the first telemetry after the answer (the fix corrects
// it), or the last one before when none came after.
struct Fix {
  double time_s = 0.0;  // of the answer
  Point at;
};

// Coordinates beyond this are skipped with a note: the vehicle refuses
// waypoints past 20 km and scenarios start within 100 km.
inline constexpr double kMaxCoordinate_m = 1.0e6;

// A vertical mark on the time axis: a phase that ended other than
// "completed", or the mission's end when it did not complete.
struct AbortMark {
  double time_s = 0.0;
  std::string label;     // "dive_from_surface aborted (exit abort)"
  bool mission = false;  // the mission_end mark, not a phase's
};

struct MissionPlot {
  std::string mission;  // the run header's mission path; "" if no header
  std::string scenario;
  Series depth_m;
  Series filtered_depth_m;
  Series setpoint_m;
  Series heading_deg;
  // Open water (empty in a tank log): the horizontal plane and the seabed.
  Path estimated;  // x_m, y_m
  Path truth;      // true_x_m, true_y_m
  Series altitude_m;
  Series seabed_m;  // depth_m + altitude_m, from lines carrying both
  std::vector<PlannedLeg> plan;
  std::vector<Fix> fixes;
  // What was read but not drawn ("log.jsonl:12: telemetry: x_m 1e+300 is
  // beyond 1000 km: skipped"); at most kMaxNotes, then skipped_notes counts.
  std::vector<std::string> notes;
  std::size_t skipped_notes = 0;
  std::vector<PhaseBand> phases;  // depth >= 1, in the order they started
  std::vector<AbortMark> aborts;  // in log order
  bool ended = false;             // a mission_end line was read
  std::string outcome;            // mission_end's outcome, exit and reason
  std::string exit;
  std::string reason;
  double first_s = 0.0;  // the earliest and latest sim_time in the log
  double last_s = 0.0;

  // The log has an estimated track: the plot gets the x-y panel.
  bool has_track() const { return !estimated.empty(); }

  // "missions/tank/tank.coral, scenario leak_phase2: aborted (exit closed_after_abort)"
  std::string title() const;
};

// Reads a log from `in`; `name` is what errors call it (a path). Unknown
// events and fields are ignored, so newer logs still plot. InvalidInput,
// naming "name:LINE: ", for a line that is not a JSON object or an event
// whose fields have the wrong types; InvalidInput, naming "name: ", for a
// log without depth telemetry.
core::Result<MissionPlot> read_log(std::istream& in, std::string_view name);

inline constexpr std::size_t kMaxNotes = 20;

// The largest mission log read (hours of telemetry are a few megabytes).
inline constexpr std::size_t kMaxLogBytes = std::size_t{1} << 30;

// The same from a file (core::read_regular_file: a FIFO or a device is
// refused, never waited on); Io when it cannot be read, Overflow past
// kMaxLogBytes.
core::Result<MissionPlot> read_log_file(const std::string& path);

}  // namespace strata::plot
