#pragma once
// `strata run`: one mission, end to end. Loads and checks the mission, starts
// the simulated vehicle on a free loopback port unless a vehicle address is
// given, connects the Tactical level to it over TCP, runs the Strategic
// executor, and reports to the console and the mission log.
//
// Kept apart from the command line so tests run whole missions in-process.
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "strategic/executor.h"
#include "tactical/tactical_level.h"

namespace strata::cli {

// Lets another thread stop a run (the studio's Stop button). cancel() is
// thread-safe, and does nothing when no run is attached.
class RunControl {
 public:
  void cancel(const std::string& reason);

 private:
  friend struct RunControlAttachment;
  std::mutex mutex_;
  std::function<void(const std::string&)> cancel_;
};

struct RunOptions {
  std::string mission;        // a .coral (CORAL) or .pl (PROLOG) file
  std::string data;           // overrides the mission's data file
  std::string scenario;       // name (in the mission's scenarios/) or path; "" nominal
  std::string params;         // vehicle parameter file; "" built in
  std::string catalogue;      // primitive catalogue; "" built in
  std::optional<std::uint64_t> seed;  // CORAL: seeded choice among enabled transitions
  std::uint64_t inference_limit = 10'000'000;  // PROLOG: inferences allowed between primitive calls
  bool realtime = false;      // the embedded vehicle on the wall clock
  double speed = 1.0;         // with realtime: simulated seconds per wall second
  std::string vehicle;        // HOST:PORT of a running vehicle; "" embedded
  std::string log;            // mission log path; "" none
  // Start the Sonar Manager (`strata sonar`, a separate process) on the
  // vehicle's sonar socket, writing its scans here; "" none.
  std::string sonar_dir;
  bool tty = false;           // a live status line instead of plain event lines
  bool handle_signals = false;  // SIGINT/SIGTERM cancel the mission (the CLI)
  double telemetry_hz = 2.0;  // telemetry asked of the vehicle, per simulated second
  bool trace = false;         // keep every primitive call in RunReport::trace (strata compare)
  // CORAL: a mission that fails verification (docs/verification.md) is not
  // run unless this is set; then it runs and the log records the failures.
  bool unverified = false;
  // Observers beside the console and the log (the studio), told after them.
  std::vector<strategic::Observer*> observers;
  // Telemetry and REPORTs as they arrive (the studio).
  std::function<void(const protocol::Telemetry&)> on_telemetry;
  std::function<void(const std::string& text, double sim_time_s)> on_report;
  std::shared_ptr<RunControl> control;  // set: the run can be stopped from another thread
  // Every line on the link (see tactical::LinkOptions::tap); for benchmarks.
  std::function<void(bool sent, std::string_view line)> wire_tap;
};

// What happened, for the summary and for tests.
struct RunReport {
  int exit_code = 0;
  std::optional<strategic::MissionResult> result;  // unset if the mission never started
  std::vector<std::string> phases;  // "initialize completed", in the order they ended
  std::uint64_t primitive_calls = 0;
  double sim_time_s = 0.0;
  double wall_time_s = 0.0;
  bool emergency_shutdown = false;  // the runner sent Figure 10's `done` itself
  bool emergency_surface = false;   // ... and before it commanded the surface (the link still worked)
  bool emergency_surfaced = false;  // ... and the vehicle answered surface_reached 1 (then or before)
  // Embedded vehicle only: its state when the run was over.
  std::optional<double> final_depth_m;
  bool vehicle_watchdog_tripped = false;
  // With RunOptions::sonar_dir: the Sonar Manager's exit status (nullopt if
  // it was not started or did not end).
  std::optional<int> sonar_exit;
  // With RunOptions::trace: every primitive call, in the order they completed.
  std::vector<tactical::CallRecord> trace;
};

// Runs the mission; console lines go to out, problems to err.
RunReport run_mission(const RunOptions& options, std::ostream& out, std::ostream& err);

}  // namespace strata::cli
