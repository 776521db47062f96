#pragma once
// Runs for the studio: one mission at a time on a thread of its own (a
// PROLOG mission on the PrologThread), on the wall clock, through the run
// library (run::RunSession), told to the page through the EventHub
// (run_start, then the RunPublisher's events, then run_end).
//
// Every run reads its inputs through the studio's Sandbox
// (RunOptions::read_file) and writes its mission log into a `runs/` folder
// beside the mission, created through the Sandbox:
// runs/YYYYMMDDTHHMMSSZ-FILE.jsonl (UTC; -2, -3... when the name is taken).
//
// Threads: start(), abort() and stop() from any thread (the HTTP workers);
// the run itself on its own thread, joined by the next start() or the
// destructor. run_here() runs on the calling thread (`strata run --studio`).
#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "run/observer.h"
#include "run/options.h"
#include "run/report.h"
#include "run/session.h"
#include "studio/event_hub.h"
#include "studio/sandbox.h"
#include "studio/server.h"
#include "tactical/catalogue.h"

namespace strata::studio {

// The name of the n-th new log for `mission` (relative) started at `utc`:
// "DIR/runs/20261125T214638Z-tank.coral.jsonl", the name every dated log
// has (tactical::dated_log_name), in runs/ beside the mission.
std::string run_log_name(const std::string& mission, std::chrono::system_clock::time_point utc, int n = 1);

// Why a run never started, as the page says it: "the mission does not
// compile: tank.coral:12:9: unknown primitive 'x' (and 1 more error)", "the
// answers file cannot be read: ...". No command names, no flags.
std::string not_started_text(const run::LoadedMission& loaded, const run::Error& error);

class StudioRunner final : public RunLauncher {
 public:
  StudioRunner(EventHub& hub, const Sandbox& sandbox, const tactical::Catalogue& catalogue)
      : hub_(hub), sandbox_(sandbox), catalogue_(catalogue) {}
  ~StudioRunner() override;

  // Overflow when a run is going; InvalidInput for what the studio cannot run.
  core::Result<void> start(const RunRequest& request) override;
  // The page's Abort: the run's safe end, outcome aborted.
  void abort() override { stop("studio", "aborted from the studio", 1, run::StopMode::Abort); }
  // The page's Stop: a hard stop (no surfacing, no done).
  void stop() override {
    stop("studio", "stopped from the studio (hard stop: the vehicle was not surfaced)", 1, run::StopMode::Hard);
  }
  // Any other cause (a signal): as run::RunSession::stop(). No run: nothing.
  void stop(const std::string& who, const std::string& reason, int exit_code,
            run::StopMode mode = run::StopMode::Interrupt);
  bool running() const { return running_; }
  // Runs started by start() get a Sonar Manager writing here ("" none).
  void set_sonar_dir(std::string dir) { sonar_dir_ = std::move(dir); }

  // Called once the inputs are loaded (or failed to load), before anything
  // moves: what the mission text holds, for a console to print.
  using OnLoaded = std::function<void(const run::LoadedMission&)>;

  // The same run on the calling thread, with more observers (the console);
  // options says everything but the mission and scenario, which come from
  // the request. Returns its report; a run that never started says why in
  // report.error (the page was told in the studio's words).
  run::RunReport run_here(const RunRequest& request, run::RunOptions options,
                          const std::vector<run::RunObserver*>& observers, const OnLoaded& on_loaded = {});

 private:
  // studio_log: the run was asked for by the page: it writes its log in
  // runs/ beside the mission.
  run::RunReport run_impl(const RunRequest& request, run::RunOptions options,
                          const std::vector<run::RunObserver*>& observers, const OnLoaded& on_loaded, bool studio_log);

  EventHub& hub_;
  const Sandbox& sandbox_;
  const tactical::Catalogue& catalogue_;
  std::mutex mutex_;  // guards thread_, session_ and stop_asked_
  std::thread thread_;
  run::RunSession* session_ = nullptr;  // the run going, if any
  bool stop_asked_ = false;             // stop() reached session_
  std::atomic<bool> running_{false};
  std::uint64_t runs_ = 0;
  std::string sonar_dir_;
};

}  // namespace strata::studio
