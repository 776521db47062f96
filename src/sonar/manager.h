#pragma once
// The Sonar Manager (the paper's §2.2): a process beside mission control
// that captures the vehicle's sonar stream on its own socket, processes it
// and passes it on for display. Here: a Capture thread (capture.h) feeding
// a Processor (processor.h) on the caller's thread, which writes the frames
// and their detections into a folder (output.h). docs/sonar.md.
//
// Use: `strata sonar` calls run_sonar_manager() on its main thread;
// `strata run --sonar DIR` or the studio can run it on a thread of theirs:
//   std::jthread sonar([&](std::stop_token stop) { summary = run_sonar_manager(options, stop); });
//   ... sonar.request_stop();  // or let the vehicle's SonarEnd finish it
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <stop_token>
#include <string>

#include "protocol/sonar_frame.h"
#include "sonar/capture.h"
#include "sonar/processor.h"

namespace strata::sonar {

struct ManagerOptions {
  CaptureOptions capture;  // host, port, connect timeout
  std::filesystem::path out_dir;
  ProcessorOptions processor;         // image size, display curve, detection thresholds
  std::size_t queue_capacity = 8192;  // pings waiting for processing before they are dropped
  bool verbose = false;               // a log line per frame written
  bool quiet = false;                 // no "connected" line: only problems and the summary
  // Lines for people (no newline): one when connected, warnings, one at the
  // end; called on the thread that runs run_sonar_manager(). Default: stderr.
  std::function<void(const std::string&)> log;
  // Tests only: called on the processing thread before each ping is processed.
  std::function<void(const protocol::SonarPing&)> before_ping;
};

enum class Outcome {
  Ended,           // the vehicle sent SonarEnd after pings
  NeverStarted,    // SonarEnd with no ping before it
  VehicleGone,     // the connection closed or reset without SonarEnd
  NeverConnected,  // refused (or unanswered) until the connect timeout
  Stopped,         // the caller's stop token
  OutputFailed,    // the folder or a file in it could not be written
};

// Exit status for `strata sonar` (sysexits): Ended, NeverStarted, Stopped 0
// (the command itself turns a stop by SIGINT/SIGTERM into 130/143);
// VehicleGone, NeverConnected 69 (EX_UNAVAILABLE); OutputFailed 74.
int exit_code(Outcome outcome);
// "ended", "never_started", "vehicle_gone", ... (the end line's "outcome").
const char* outcome_name(Outcome outcome);

struct ManagerSummary {
  Outcome outcome = Outcome::Ended;
  int exit_code = 0;
  std::string message;          // for people, as in the end line
  CaptureCounts capture;        // what was read
  std::uint64_t processed = 0;  // pings processed (painted, echo looked for)
  std::uint64_t unusable = 0;   // pings with no bins or range, or not-a-number fields
  std::uint64_t frames = 0;     // frames written
  double last_time_s = 0.0;     // the vehicle's time of the last frame read
  std::optional<protocol::SonarEnd> end;
  std::optional<protocol::SonarStatus> last_status;
};

// Runs until the stream ends (SonarEnd or the connection closing), the
// connection cannot be made, writing fails, or `stop` is requested; then
// writes the frame under way, if any, and the summary line
// {"event":"end",...} in DIR/sonar.jsonl. Blocks; starts and joins the
// capture thread. Expected failures are in the summary, not thrown.
ManagerSummary run_sonar_manager(const ManagerOptions& options, const std::stop_token& stop = {});

}  // namespace strata::sonar
