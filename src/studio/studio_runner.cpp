#include "studio/studio_runner.h"

#include <sstream>

#include "studio/mission_model.h"
#include "studio/run_publisher.h"

namespace strata::studio {

StudioRunner::~StudioRunner() {
  stop();
  std::lock_guard lock(mutex_);
  if (thread_.joinable()) thread_.join();
}

core::Result<void> StudioRunner::start(const RunRequest& request) {
  if (request.mission.extension() != ".coral") {
    return core::Error{core::ErrorCode::InvalidInput, "the studio runs CORAL missions (.coral)"};
  }
  std::lock_guard lock(mutex_);
  if (running_) return core::Error{core::ErrorCode::Overflow, "a run is going; stop it first"};
  if (thread_.joinable()) thread_.join();
  running_ = true;
  thread_ = std::thread([this, request] {
    run::RunOptions o;
    o.sonar_dir = sonar_dir_;
    std::ostringstream err;
    run_here(request, o, {}, err);
    running_ = false;
  });
  return core::Result<void>();
}

void StudioRunner::stop(const std::string& who, const std::string& reason, int exit_code) {
  std::lock_guard lock(mutex_);
  if (session_) session_->stop(who, reason, exit_code);
}

run::RunReport StudioRunner::run_here(const RunRequest& request, run::RunOptions o,
                                      const std::vector<run::RunObserver*>& observers, std::ostream& err) {
  RunPublisher publisher(hub_);
  const std::uint64_t run = ++runs_;
  auto model = compile_mission(sandbox_, request.relative, std::nullopt, catalogue_);
  hub_.publish("run_start", {{"run", run},
                             {"mission", request.relative},
                             {"scenario", request.scenario.empty() ? "nominal" : request.scenario},
                             {"speed", request.speed},
                             {"nets", model.model["nets"]}});
  o.mission = request.mission.string();
  // From the page: the file the server checked inside the root, never the
  // name as a path.
  o.scenario = request.scenario_file.empty() ? request.scenario : request.scenario_file.string();
  if (o.vehicle.empty()) {
    o.realtime = true;  // watching live is on the wall clock
    o.speed = request.speed;
  }
  run::RunSession session(o);
  for (run::RunObserver* obs : observers) session.add_observer(*obs);
  session.add_observer(publisher);
  {
    std::lock_guard lock(mutex_);
    session_ = &session;
  }
  // Problems before the mission starts (it fails verification, say) reach
  // the page as the run's end, with what strata run would print.
  std::ostringstream problems;
  run::RunReport report = session.run(problems);
  {
    std::lock_guard lock(mutex_);
    session_ = nullptr;
  }
  err << problems.str();
  if (!report.result) {
    hub_.publish("run_end", {{"outcome", "failed"}, {"exit", ""}, {"reason", problems.str()}, {"t", 0.0}});
  }
  return report;
}

}  // namespace strata::studio
