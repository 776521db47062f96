#include "cli/studio_runner.h"

#include <sstream>

#include "studio/mission_model.h"
#include "studio/run_publisher.h"

namespace strata::cli {

StudioRunner::~StudioRunner() {
  stop();
  std::lock_guard lock(mutex_);
  if (thread_.joinable()) thread_.join();
}

core::Result<void> StudioRunner::start(const studio::RunRequest& request) {
  if (request.mission.extension() != ".coral") {
    return core::Error{core::ErrorCode::InvalidInput, "the studio runs CORAL missions (.coral)"};
  }
  std::lock_guard lock(mutex_);
  if (running_) return core::Error{core::ErrorCode::Overflow, "a run is going; stop it first"};
  if (thread_.joinable()) thread_.join();
  running_ = true;
  thread_ = std::thread([this, request] {
    RunOptions o;
    o.handle_signals = false;
    o.sonar_dir = sonar_dir_;
    std::ostringstream out, err;
    run_here(request, o, out, err);
    running_ = false;
  });
  return core::Result<void>();
}

void StudioRunner::stop() { control_->cancel("stopped from the studio"); }

RunReport StudioRunner::run_here(const studio::RunRequest& request, RunOptions o, std::ostream& out,
                                 std::ostream& err) {
  studio::RunPublisher publisher(hub_);
  const std::uint64_t run = ++runs_;
  auto model = studio::compile_mission(sandbox_, request.relative, std::nullopt, catalogue_);
  hub_.publish("run_start", {{"run", run},
                             {"mission", request.relative},
                             {"scenario", request.scenario.empty() ? "nominal" : request.scenario},
                             {"speed", request.speed},
                             {"nets", model.model["nets"]}});
  o.mission = request.mission.string();
  o.scenario = request.scenario;
  if (o.vehicle.empty()) {
    o.realtime = true;  // watching live is on the wall clock
    o.speed = request.speed;
  }
  o.observers.push_back(&publisher);
  o.on_telemetry = [&publisher](const protocol::Telemetry& t) {
    publisher.telemetry(t.sim_time_s, t.depth_m.value_or(0.0), t.setpoint_m);
  };
  o.on_report = [&publisher](const std::string& text, double t) { publisher.report(t, text); };
  o.control = control_;
  // Problems before the mission starts (it fails verification, say) reach
  // the page as the run's end, with what strata run would print.
  std::ostringstream problems;
  RunReport report = run_mission(o, out, problems);
  err << problems.str();
  if (!report.result) {
    hub_.publish("run_end", {{"outcome", "failed"}, {"exit", ""}, {"reason", problems.str()}, {"t", 0.0}});
  }
  return report;
}

}  // namespace strata::cli
