#pragma once
// The mission log: JSON Lines, one event per line, keys in a fixed order.
// The first line is the run header; every line is flushed as soon as it is
// written, so a crash loses nothing already logged.
//
// Determinism rule: every field whose value depends on the wall clock is
// named wall_* (wall_time, wall_latency_us). Two runs of the same inputs in
// lockstep give logs that differ only in those fields; strip_wall_fields()
// removes them for comparison. Simulation times come from the caller and are
// written rounded to the microsecond; the log reads no clock of its own
// except through the WallTimeSource it is given.
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/result.h"
#include "tactical/log_line.h"

namespace strata::tactical {

// Where the log takes its wall_* values from (the system clocks, or fixed ones
// in tests).
struct WallTimeSource {
  std::function<std::chrono::system_clock::time_point()> now;        // wall_time
  std::function<std::chrono::steady_clock::time_point()> monotonic;  // wall_latency_us
  // The system's clocks.
  static WallTimeSource system();
};

// What the run header records: enough to say which inputs made the log.
struct RunInfo {
  std::string version;         // strata's version
  std::string mission;         // the mission file, as given
  std::string mission_sha256;  // see sha256.h
  std::string data;            // the mission data file; "" for none (logged as null)
  std::string data_sha256;
  std::string scenario;  // the vehicle scenario's name
  std::uint64_t seed = 0;
  std::string clock = "lockstep";  // "lockstep" | "wall"
  std::string params{};            // the vehicle parameter file; "" for the built-in parameters (not logged)
  std::string params_sha256{};
  // Parameters set over those (a campaign's perturbed case), in their order;
  // logged only when there are some.
  std::vector<std::pair<std::string, double>> param_overrides{};
};

class MissionLog {
 public:
  // The one way a mission log file comes to be (the run calls it; the CLI
  // and the studio only name the file or its folder). Creates path, or
  // replaces a regular file there, and writes the run header. Never written
  // through: a symbolic link at path, a FIFO, a device or a folder (an Io
  // error, at once, never waiting on a FIFO). InvalidInput if run.clock is
  // neither lockstep nor wall.
  static core::Result<MissionLog> open(const std::string& path, const RunInfo& run,
                                       WallTimeSource wall = WallTimeSource::system());
  // A new log in `folder` (made if missing), named for the mission and the
  // time (dated_log_name): never an existing file; -2, -3... when the name
  // is taken, up to 100,000 in one second.
  static core::Result<MissionLog> open_dated(const std::string& folder, const std::string& mission, const RunInfo& run,
                                             WallTimeSource wall = WallTimeSource::system());
  // The same onto a stream the caller owns and keeps alive (tests).
  static core::Result<MissionLog> to_stream(std::ostream& out, const RunInfo& run,
                                            WallTimeSource wall = WallTimeSource::system());

  MissionLog(MissionLog&&) = default;
  MissionLog& operator=(MissionLog&&) = default;
  MissionLog(const MissionLog&) = delete;
  MissionLog& operator=(const MissionLog&) = delete;
  ~MissionLog() = default;

  // {"event":"request","id","primitive","message","sim_time"}. message is the
  // script message without its id (RenderedCall::text()).
  void request(std::uint64_t id, std::string_view primitive, std::string_view message, double sim_time_s);
  // {"event":"reply","id","result","sim_time","latency_sim_s","wall_latency_us"}.
  // The latencies are measured from the request of the same id; null if no
  // such request was logged. result is what the vehicle answered (1/0, "done",
  // an error object...).
  void reply(std::uint64_t id, const nlohmann::ordered_json& result, double sim_time_s);
  // {"event":"telemetry","sim_time", ...fields}; fields is an object such as
  // {"depth_m": 1.2, "depth_rate_mps": 0.1}.
  void telemetry(double sim_time_s, const nlohmann::ordered_json& fields);
  // {"event":"report","text","sim_time"}
  void report(std::string_view text, double sim_time_s);
  // {"event":"error","message","sim_time"}
  void error(std::string_view message, double sim_time_s);
  // {"event": name, ...fields}: for events defined later (firings, phases).
  // fields is an object; it should carry its own sim_time.
  void event(std::string_view name, const nlohmann::ordered_json& fields);
  // Any object, as one line. Wall-clock-dependent keys must be named wall_*.
  void write(const nlohmann::ordered_json& line);
  // The same, written field by field (the busiest lines).
  void write(LogLine&& line);

  // Bounds the log to max_bytes (0: no bound). Past max_bytes minus a
  // reserve for the run's last records (an eighth of it, at most 1 MiB) it
  // writes {"event":"log_limit","max_bytes","bytes"} and calls on_full
  // once (the run then ends safely); past max_bytes every line is dropped
  // and counted. So a runaway mission cannot fill the disk.
  void limit(std::uint64_t max_bytes, std::function<void()> on_full);
  bool full() const { return full_; }
  std::uint64_t bytes() const { return bytes_; }
  std::uint64_t dropped() const { return dropped_; }

  // Ok, or the first write failure; once a write failed, later ones are dropped.
  core::Result<void> status() const;
  // Lines written, the header included.
  std::size_t lines() const { return lines_; }
  const std::string& path() const { return path_; }

 private:
  struct Pending {
    double sim_time_s = 0;
    std::chrono::steady_clock::time_point wall;
  };

  MissionLog(std::unique_ptr<std::ostream> owned, std::ostream* out, std::string path, WallTimeSource wall);
  void write_text(const std::string& text);  // one whole line, its newline included
  static core::Result<MissionLog> start(MissionLog log, const RunInfo& run);

  std::unique_ptr<std::ostream> owned_;
  std::ostream* out_ = nullptr;
  std::string path_;
  WallTimeSource wall_;
  std::unordered_map<std::uint64_t, Pending> pending_;
  std::size_t lines_ = 0;
  std::uint64_t bytes_ = 0;
  std::uint64_t max_bytes_ = 0;  // 0: no bound
  std::function<void()> on_full_;
  bool full_ = false;
  std::uint64_t dropped_ = 0;
  std::optional<core::Error> failure_;
};

// The run header line's object (without writing it).
nlohmann::ordered_json run_header(const RunInfo& run, std::chrono::system_clock::time_point wall_time);

// The name of the n-th (1-based) new log of `mission` started at `utc`:
// "20261125T214638Z-tank.coral.jsonl", then "...-tank.coral-2.jsonl" (UTC;
// the mission's file name, so runs of tank.coral and tank.pl are told
// apart). The CLI's dated logs and the studio's runs/ share it.
std::string dated_log_name(const std::string& mission, std::chrono::system_clock::time_point utc, int n = 1);

// "2024-05-01T12:34:56.123456Z"
std::string iso8601_utc(std::chrono::system_clock::time_point t);

// One log line with every wall_* key removed, at any depth, re-serialised
// compactly in the same key order. A line that is not JSON comes back as is.
std::string strip_wall_fields(std::string_view line);
// The same for each line of a whole log.
std::string strip_wall_fields_from_log(std::string_view text);

// A simulation time as logged: rounded to the microsecond.
double log_time(double sim_time_s);

}  // namespace strata::tactical
