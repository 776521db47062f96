#pragma once
// One run as a library object (docs/architecture.md): load the inputs (mission,
// data, scenario, catalogue, parameters), open the vehicle (embedded in
// lockstep, embedded on the wall clock, or a remote one), start the
// Strategic executor, drive it, and end it — always through one path:
//
//   interrupt the executor; surface the vehicle unless the mission completed
//   or ran its own abort path to `done`, or the link is gone (SafeEnd); send
//   `done`; let an embedded vehicle settle; write `vehicle_final` and
//   `mission_end` (outcome, reason, what ended it, the exit code) and flush
//   the log; tell the observers run_ended().
//
// Whatever ends the run takes that path: the mission completing, an EXEC
// answered 0, a lost link, a stall, runaway or crashing rules, halt, stop()
// (a signal, the studio's Stop), the simulated-time limit, an internal error.
//
// The CLI and the studio both build a RunSession; `strata compare` runs two.
//
// Threads: run() on one thread, which becomes the run's event loop (and, for
// PROLOG rules, SWI-Prolog's thread). stop() from any thread, at any time.
#include <chrono>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"
#include "run/error.h"
#include "run/loaded_mission.h"
#include "run/observer.h"
#include "run/options.h"
#include "run/report.h"

namespace strata::run {

// How a stop request ends the run.
//  Interrupt: the safe end (surface, then done); the mission's outcome is
//             failed, with the stop's reason (a signal).
//  Abort:     the same safe end, but the outcome is aborted: the operator's
//             deliberate abort (the studio's Abort button).
//  Hard:      no safe end: the executor is cancelled, nothing more is sent
//             to the vehicle (no surface, no done; a safe end already going
//             is abandoned, as a second Ctrl-C does), the link is closed and
//             the vehicle is left to its own watchdog. Outcome failed.
enum class StopMode { Interrupt, Abort, Hard };
std::string_view to_string(StopMode mode);  // "interrupt", "abort", "hard"

class RunSession {
 public:
  explicit RunSession(RunOptions options);
  ~RunSession();
  RunSession(const RunSession&) = delete;
  RunSession& operator=(const RunSession&) = delete;

  // Observers are told in the order added; each must outlive run().
  void add_observer(RunObserver& observer);

  // Loads and checks the inputs (mission, catalogue, answers, vehicle
  // parameters, scenario, data) and returns why the run cannot start, if it
  // cannot. Either way loaded() then holds what was found in the mission
  // text (warnings too), for the caller to print before the run starts.
  // Optional: run() loads first when it was not called. Call at most once.
  core::Result<void, Error> load();
  // What load() loaded and found. Valid after load(), until the session goes.
  const LoadedMission& loaded() const { return *loaded_; }

  // Runs the mission to its end on the calling thread and returns what
  // happened. Nothing is printed: a run that cannot start (a bad mission,
  // a file not there, a vehicle not reachable) leaves report.result unset
  // and says why in report.error. Call once.
  RunReport run();

  // Ends the run through the safe end. `who` names the cause for the report
  // and the log ("SIGINT", "studio"), `reason` says it to people, exit_code
  // is the run's exit code. A second call cuts the safe end short: replies
  // are no longer waited for, but the log is still closed. Thread-safe,
  // never blocks; before run() it stops the run as soon as it starts, after
  // run() it does nothing.
  // `mode` says whether the safe end runs and what the outcome is; a later
  // Hard request cuts a safe end short.
  void stop(const std::string& who, const std::string& reason, int exit_code, StopMode mode = StopMode::Interrupt);

 private:
  class Run;
  friend class Run;
  struct StopRequest {
    std::string who, reason;
    int exit_code = 0;
    StopMode mode = StopMode::Interrupt;
  };

  RunOptions options_;
  std::unique_ptr<LoadedMission> loaded_;
  std::optional<core::Result<void, Error>> load_result_;  // once load() ran
  // When load() began: the run's wall time counts from there (RunReport::wall_time_s).
  std::optional<std::chrono::steady_clock::time_point> load_started_;
  std::vector<RunObserver*> observers_;
  std::mutex mutex_;  // guards the three below
  std::optional<StopRequest> stop_;
  int stop_requests_ = 0;
  bool hard_requested_ = false;  // some request was Hard
  Run* active_ = nullptr;        // set while run() drives the mission
};

}  // namespace strata::run
