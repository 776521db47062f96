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
  std::vector<PhaseBand> phases;  // depth >= 1, in the order they started
  std::vector<AbortMark> aborts;  // in log order
  bool ended = false;             // a mission_end line was read
  std::string outcome;            // mission_end's outcome, exit and reason
  std::string exit;
  std::string reason;
  double first_s = 0.0;  // the earliest and latest sim_time in the log
  double last_s = 0.0;

  // "missions/tank/tank.coral, scenario leak_phase2: aborted (exit closed_after_abort)"
  std::string title() const;
};

// Reads a log from `in`; `name` is what errors call it (a path). Unknown
// events and fields are ignored, so newer logs still plot. InvalidInput,
// naming "name:LINE: ", for a line that is not a JSON object or an event
// whose fields have the wrong types; InvalidInput, naming "name: ", for a
// log without depth telemetry.
core::Result<MissionPlot> read_log(std::istream& in, std::string_view name);

// The largest mission log read (hours of telemetry are a few megabytes).
inline constexpr std::size_t kMaxLogBytes = std::size_t{1} << 30;

// The same from a file (core::read_regular_file: a FIFO or a device is
// refused, never waited on); Io when it cannot be read, Overflow past
// kMaxLogBytes.
core::Result<MissionPlot> read_log_file(const std::string& path);

}  // namespace strata::plot
