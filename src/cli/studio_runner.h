#pragma once
// Runs for the studio: one mission at a time on a thread of its own, on the
// wall clock, told to the page through the EventHub (run_start, then the
// RunPublisher's events, then run_end).
//
// Threads: start() and stop() from any thread (the HTTP workers); the run
// itself on its own thread, joined by the next start() or the destructor.
#include <atomic>
#include <memory>
#include <mutex>
#include <thread>

#include "cli/mission_run.h"
#include "studio/event_hub.h"
#include "studio/sandbox.h"
#include "studio/server.h"
#include "tactical/catalogue.h"

namespace strata::cli {

class StudioRunner {
 public:
  StudioRunner(studio::EventHub& hub, const studio::Sandbox& sandbox, const tactical::Catalogue& catalogue)
      : hub_(hub), sandbox_(sandbox), catalogue_(catalogue) {}
  ~StudioRunner();

  // Overflow when a run is going; InvalidInput for what the studio cannot run.
  core::Result<void> start(const studio::RunRequest& request);
  void stop();
  bool running() const { return running_; }
  // Runs started by start() get a Sonar Manager writing here ("" none).
  void set_sonar_dir(std::string dir) { sonar_dir_ = std::move(dir); }

  // The same run on the calling thread (`strata run --studio`); returns its report.
  RunReport run_here(const studio::RunRequest& request, RunOptions options, std::ostream& out, std::ostream& err);

 private:
  studio::EventHub& hub_;
  const studio::Sandbox& sandbox_;
  const tactical::Catalogue& catalogue_;
  std::mutex mutex_;
  std::thread thread_;
  std::atomic<bool> running_{false};
  std::uint64_t runs_ = 0;
  std::shared_ptr<RunControl> control_ = std::make_shared<RunControl>();
  std::string sonar_dir_;
};

}  // namespace strata::cli
