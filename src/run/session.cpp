#include "run/session.h"

#include <chrono>
#include <cstdlib>
#include <algorithm>
#include <exception>
#include <filesystem>
#include <map>

#include <asio.hpp>
#include <fmt/format.h>

#include "core/exit_codes.h"
#include "run/inputs.h"
#include "run/loaded_mission.h"
#include "run/safe_end.h"
#include "run/sonar_child.h"
#include "strategic/coral_engine.h"
#include "strategic/log_observer.h"
#include "strategic/prolog_executor.h"
#include "tactical/mission_log.h"
#include "tactical/tactical_level.h"
#include "tactical/vehicle_link.h"
#include "vehicle/server.h"

namespace strata::run {
namespace {

using strategic::MissionResult;
using strategic::Outcome;

// Lockstep: wall seconds allowed per simulated second of a call (>= 100x real time).
constexpr double kLockstepWallPerSim = 0.01;
constexpr const char* kShutdown = "shutdown_network";

// Records the depth-1 phases as they end, for the summary.
class PhaseRecorder final : public strategic::Observer {
 public:
  explicit PhaseRecorder(std::vector<std::string>& phases) : phases_(phases) {}
  void phase_started(const strategic::PhaseStart& e) override { depth_[e.instance] = e.depth; }
  void phase_ended(const strategic::PhaseEnd& e) override {
    auto it = depth_.find(e.instance);
    if (it == depth_.end()) return;
    if (it->second == 1) {
      phases_.push_back(fmt::format("{} {}", e.name, e.cancelled ? "cancelled" : e.exit_index == 0 ? "completed" : "aborted"));
    }
    depth_.erase(it);
  }

 private:
  std::vector<std::string>& phases_;
  std::map<strategic::InstanceId, std::size_t> depth_;
};

bool link_error(const MissionResult& r) {
  return r.call_error && (*r.call_error == core::ErrorCode::Timeout || *r.call_error == core::ErrorCode::Closed);
}

}  // namespace

// The objects of one run, alive inside RunSession::run(). Each stage is a
// member function; those before the mission return an exit code (0: go on).
class RunSession::Run {
 public:
  Run(RunSession& session, std::ostream& err)
      : session_(session), o_(session.options_), err_(err), wall_start_(std::chrono::steady_clock::now()) {}

  RunReport execute();

  // On the loop: a stop request arrived (RunSession::stop()).
  void on_stop();
  // Any thread, under the session's mutex: wake an executor that holds the loop.
  void interrupt(const std::string& reason) {
    if (executor_) executor_->interrupt(reason);
  }
  asio::io_context& io() { return io_; }

 private:
  int fail(int code) {
    report_.exit_code = code;
    return code;
  }
  int load_inputs();
  int open_log();
  int open_vehicle();
  int connect();
  int start_sonar();
  void build_levels();
  void drive();
  void mission_ended(const MissionResult& result);
  bool needs_safe_end(const MissionResult& result) const;
  void wrap_up();
  void close_sonar();
  void finish_report();
  void write_end_of_log();
  void stop_here(const std::string& who, const std::string& reason, int exit_code);
  void check_limits();
  void note(const std::string& text, std::optional<double> t = std::nullopt) {
    for (RunObserver* o : session_.observers_) o->note(text, t);
  }

  RunSession& session_;
  const RunOptions& o_;
  std::ostream& err_;
  std::chrono::steady_clock::time_point wall_start_;
  RunReport report_;

  LoadedMission loaded_;
  std::optional<tactical::MissionLog> log_;
  asio::io_context io_;
  std::vector<std::string> vehicle_log_;
  std::optional<vehicle::Simulation> sim_;
  std::unique_ptr<vehicle::VehicleServer> server_;
  tactical::LinkOptions link_options_;
  std::optional<std::uint16_t> sonar_port_;  // as hello announced it
  std::shared_ptr<tactical::VehicleLink> link_;
  std::optional<SonarChild> sonar_;
  std::optional<tactical::TacticalLevel> tactical_;
  std::optional<strategic::TacticalTactics> tactics_;
  std::unique_ptr<strategic::Executor> executor_;
  std::optional<strategic::LogObserver> log_observer_;
  std::optional<PhaseRecorder> phase_recorder_;
  std::optional<SafeEnd> safe_end_;
  bool mission_sent_done_ = false;
  bool safe_end_running_ = false;
  bool finished_ = false;
  std::optional<std::string> internal_error_;
};

RunSession::RunSession(RunOptions options) : options_(std::move(options)) {}
RunSession::~RunSession() = default;

void RunSession::add_observer(RunObserver& observer) { observers_.push_back(&observer); }

void RunSession::stop(const std::string& who, const std::string& reason, int exit_code) {
  std::lock_guard lock(mutex_);
  ++stop_requests_;
  if (!stop_) stop_ = StopRequest{who, reason, exit_code};
  if (!active_) return;
  Run* run = active_;
  asio::post(run->io(), [run] { run->on_stop(); });
  run->interrupt(stop_->reason);
}

RunReport RunSession::run(std::ostream& err) {
  Run run(*this, err);
  return run.execute();
}

RunReport RunSession::Run::execute() {
  report_.lockstep = !o_.realtime;
  int code = load_inputs();
  if (code == kExitOk) code = open_log();
  if (code == kExitOk) code = open_vehicle();
  if (code == kExitOk) {
    std::lock_guard lock(session_.mutex_);
    session_.active_ = this;
  }
  if (code == kExitOk) code = connect();
  if (code == kExitOk) code = start_sonar();
  if (code == kExitOk) {
    build_levels();
    drive();
  }
  {
    std::lock_guard lock(session_.mutex_);
    session_.active_ = nullptr;
  }
  // Handlers still queued (a closed socket's last callbacks, a late stop
  // request) run now, before the objects they point at go.
  io_.restart();
  io_.poll();
  if (code != kExitOk) {
    report_.exit_code = code;
    for (RunObserver* obs : session_.observers_) obs->run_ended(report_);
    return report_;
  }
  close_sonar();
  finish_report();
  write_end_of_log();
  for (RunObserver* obs : session_.observers_) obs->run_ended(report_);
  return report_;
}

int RunSession::Run::load_inputs() {
  if (auto r = load_mission(o_, loaded_, err_); r != kExitOk) return fail(r);
  report_.mission_name = loaded_.name;
  return kExitOk;
}

int RunSession::Run::open_log() {
  if (o_.log.empty()) return kExitOk;
  auto opened = tactical::MissionLog::open(o_.log, run_info(o_, loaded_));
  if (!opened) {
    err_ << "strata run: cannot write the mission log: " << opened.error().message << "\n";
    return fail(kExitIo);
  }
  log_ = std::move(opened.value());
  report_.log_path = log_->path();
  if (o_.seed) log_->write({{"event", "choice"}, {"seed", *o_.seed}});
  if (loaded_.verification) log_->write(verification_record(*loaded_.verification, o_.unverified));
  return kExitOk;
}

int RunSession::Run::open_vehicle() {
  if (!o_.vehicle.empty()) {
    auto endpoint = parse_listen(o_.vehicle);
    if (!endpoint) {
      err_ << "strata run: --vehicle: " << endpoint.error().message << "\n";
      return fail(kExitUsage);
    }
    link_options_.host = endpoint.value().first;
    link_options_.port = endpoint.value().second;
    if (link_options_.port == 0) {
      err_ << "strata run: --vehicle needs a port (HOST:PORT)\n";
      return fail(kExitUsage);
    }
    return kExitOk;
  }
  sim_.emplace(loaded_.params, loaded_.scenario);
  vehicle::ServerOptions so;
  so.clock = o_.realtime ? protocol::ClockMode::Wall : protocol::ClockMode::Lockstep;
  so.speed = o_.speed;
  // The embedded vehicle's own log ("6.0 s: watchdog: ..."). What it says
  // while the link works also reaches us as protocol events, so these are
  // kept and shown only for the time after we last heard from it.
  so.log = [this](const std::string& line) { vehicle_log_.push_back(line); };
  server_ = std::make_unique<vehicle::VehicleServer>(io_, *sim_, so);
  if (auto r = server_->start(); !r) {
    err_ << "strata run: cannot start the simulated vehicle: " << r.error().message << "\n";
    return fail(kExitIo);
  }
  link_options_.port = server_->port();
  // In lockstep the vehicle answers within microseconds: a second of
  // silence is a lost link, not a slow vehicle.
  if (!o_.realtime) link_options_.reply_timeout = std::chrono::milliseconds(1000);
  return kExitOk;
}

int RunSession::Run::connect() {
  link_options_.tap = o_.wire_tap;
  link_ = tactical::VehicleLink::create(io_, link_options_);
  std::optional<core::Result<protocol::Welcome>> welcome;
  link_->connect([&](core::Result<protocol::Welcome> w) { welcome = std::move(w); });
  while (!welcome && io_.run_one() > 0) {
  }
  if (!welcome || !welcome->ok()) {
    err_ << "strata run: "
         << (welcome ? welcome->error().message : std::string("the vehicle link ended before hello")) << "\n";
    return fail(kExitIo);
  }
  const protocol::Welcome& w = welcome->value();
  report_.lockstep = w.clock == protocol::ClockMode::Lockstep;
  sonar_port_ = w.sonar_port;
  if (log_) {
    // The vehicle's own word on its clock (the header says what was asked).
    // No address: the port is chosen at random and the log must not vary.
    log_->write({{"event", "vehicle"},
                 {"name", w.vehicle_name},
                 {"clock", report_.lockstep ? "lockstep" : "wall"},
                 {"embedded", o_.vehicle.empty()}});
  }
  note(fmt::format("vehicle {} at {}:{} ({}{})", w.vehicle_name, link_options_.host, link_options_.port,
                   report_.lockstep ? "lockstep" : "wall clock",
                   o_.vehicle.empty() ? fmt::format(", embedded, scenario {}", scenario_name(o_)) : ""));
  return kExitOk;
}

int RunSession::Run::start_sonar() {
  if (o_.sonar_dir.empty()) return kExitOk;
  auto started = start_sonar_manager(o_.sonar_dir, link_options_.host, sonar_port_, io_,
                                     server_ ? server_->sonar() : nullptr);
  if (!started) {
    err_ << "strata run: --sonar: " << started.error().message << "\n";
    return fail(exit_code_for_input(started.error()));
  }
  sonar_.emplace(std::move(started).value());
  note(fmt::format("sonar manager: pid {}, scans in {}", sonar_->pid(), o_.sonar_dir));
  if (log_) log_->write({{"event", "sonar_manager"}, {"dir", o_.sonar_dir}});
  return kExitOk;
}

void RunSession::Run::build_levels() {
  tactical_.emplace(io_, loaded_.catalogue, link_, loaded_.cursor ? &*loaded_.cursor : nullptr,
                    log_ ? &*log_ : nullptr);
  // Wall clock: a call may take its simulated time divided by the speed.
  // Lockstep: the vehicle computes a call's simulated time as fast as it
  // can; allow for at least 100x real time (a 1 h sleep may take 36 s of
  // wall time on a slow machine) on top of the link's own timeout.
  tactical_->set_wall_seconds_per_sim_second(report_.lockstep ? kLockstepWallPerSim : 1.0 / o_.speed);
  tactical_->on_report([this](const std::string& text, double t) {
    for (RunObserver* obs : session_.observers_) obs->report(text, t);
  });
  tactical_->on_telemetry([this](const protocol::Telemetry& t) {
    report_.last_telemetry = t;
    for (RunObserver* obs : session_.observers_) obs->telemetry(t);
    check_limits();
  });
  tactical_->on_vehicle_event([this](const protocol::Event& e) {
    // "exec submerge failed: ...": the vehicle's reason for an answer of 0.
    if (e.text.find(" failed: ") != std::string::npos) report_.vehicle_reason = e.text;
    for (RunObserver* obs : session_.observers_) obs->vehicle_event(e.text, e.sim_time_s);
  });
  tactical_->on_call([this](const tactical::CallRecord& c) {
    if (o_.trace) report_.trace.push_back(c);
    if (c.primitive == kShutdown && c.value == true && !safe_end_running_) mission_sent_done_ = true;
    if (c.error.starts_with("vehicle error ")) report_.vehicle_reason = c.error;
    check_limits();
  });
  if (o_.telemetry_hz > 0) {
    link_->send(protocol::make_telemetry(0, o_.telemetry_hz), [](core::Result<protocol::VehicleMessage>) {});
  }
  tactics_.emplace(*tactical_);
  if (loaded_.program) {
    strategic::EngineOptions engine_options;
    engine_options.seed = o_.seed;
    executor_ = std::make_unique<strategic::CoralEngine>(*loaded_.program, *tactics_, engine_options);
  } else {
    strategic::PrologOptions prolog_options;
    prolog_options.inference_limit = o_.inference_limit;
    executor_ = std::make_unique<strategic::PrologExecutor>(*loaded_.rules, *tactics_, loaded_.catalogue,
                                                            prolog_options);
  }
  if (log_) {
    log_observer_.emplace(*log_);
    executor_->add_observer(*log_observer_);
  }
  phase_recorder_.emplace(report_.phases);
  executor_->add_observer(*phase_recorder_);
  for (RunObserver* obs : session_.observers_) executor_->add_observer(*obs);
  safe_end_.emplace(*tactical_, loaded_.catalogue, [this](const std::string& text) { note(text); });
  link_->on_lost([this](const core::Error& e) {
    report_.link_lost = true;
    report_.link_lost_why = e.message;
    if (executor_->running()) executor_->cancel(fmt::format("lost the link to the vehicle: {}", e.message));
  });
}

// Runs the executor and the safe end on the loop until both are over. An
// exception out of a handler is an internal error: the run still ends
// through the safe end, and exits 70.
void RunSession::Run::drive() {
  {
    std::lock_guard lock(session_.mutex_);
    if (session_.stop_) asio::post(io_, [this] { on_stop(); });  // asked before the mission started
  }
  executor_->start([this](const MissionResult& r) { mission_ended(r); });
  while (!finished_) {
    try {
      if (io_.run_one() == 0) break;
    } catch (const std::exception& e) {
      if (internal_error_) throw;  // a second one: the end path itself is broken
      internal_error_ = e.what();
      note(fmt::format("internal error: {}; ending the run", e.what()));
      if (executor_->running()) executor_->cancel(fmt::format("internal error: {}", e.what()));
    }
  }
}

void RunSession::Run::on_stop() {
  std::optional<StopRequest> stop;
  int requests = 0;
  {
    std::lock_guard lock(session_.mutex_);
    stop = session_.stop_;
    requests = session_.stop_requests_;
  }
  if (!stop || finished_ || !executor_) return;
  if (executor_->running()) {
    executor_->cancel(stop->reason);
  } else if (requests > 1 && safe_end_running_) {
    report_.hurried = true;
    safe_end_->abandon();
  }
}

// A stop decided on the loop itself (a limit): as RunSession::stop().
void RunSession::Run::stop_here(const std::string& who, const std::string& reason, int exit_code) {
  {
    std::lock_guard lock(session_.mutex_);
    if (session_.stop_) return;
    ++session_.stop_requests_;
    session_.stop_ = StopRequest{who, reason, exit_code};
  }
  // Posted: this may be inside a reply's handling, before the executor has it.
  asio::post(io_, [this] { on_stop(); });
}

void RunSession::Run::check_limits() {
  if (!report_.lockstep || !executor_ || !executor_->running()) return;
  if (tactical_->sim_time_s() > o_.max_sim_time_s) {
    stop_here("limit",
              fmt::format("the simulated-time limit was reached ({:.0f} s; --max-sim-time sets it)",
                          o_.max_sim_time_s),
              kExitAbort);
  }
}

bool RunSession::Run::needs_safe_end(const MissionResult& r) const {
  if (r.outcome == Outcome::Completed) return false;
  // The mission's own abort path ran to Figure 10's `done`: nothing to add.
  if (mission_sent_done_) return false;
  return link_->connected() && safe_end_->possible();
}

void RunSession::Run::mission_ended(const MissionResult& r) {
  report_.result = r;
  if (!needs_safe_end(r)) {
    wrap_up();
    return;
  }
  const bool link_gone = link_error(r);
  const std::string plan = safe_end_->plan(link_gone);
  note(fmt::format("the mission did not complete and did not end with done; strata sends {} (a second "
                   "Ctrl-C stops waiting)",
                   plan),
       r.sim_time_s);
  if (log_) {
    log_->write({{"event", "emergency"}, {"action", plan}, {"sim_time", tactical::log_time(r.sim_time_s)}});
  }
  safe_end_running_ = true;
  safe_end_->run(link_gone, [this] {
    report_.emergency_shutdown = safe_end_->shutdown_sent();
    report_.shutdown_error = safe_end_->shutdown_error();
    report_.emergency_surface = safe_end_->surface_commanded();
    report_.emergency_surfaced = safe_end_->surfaced();
    wrap_up();
  });
}

// The link closes and an embedded vehicle is left to settle (its watchdog
// may be surfacing it) before the loop ends.
void RunSession::Run::wrap_up() {
  safe_end_running_ = false;
  link_->close();
  if (!server_) {
    finished_ = true;
    return;
  }
  server_->when_settled([this] {
    server_->stop();
    finished_ = true;
  });
}

// The vehicle's last pings and its end frame reach the manager, then it
// writes its last scan and ends. A vehicle of its own (--vehicle) sends no
// end frame when our run ends: the manager is stopped after a moment.
void RunSession::Run::close_sonar() {
  if (!sonar_) return;
  drain_sonar(io_, server_ ? server_->sonar() : nullptr);
  report_.sonar_exit = sonar_->wait(server_ ? std::chrono::seconds(20) : std::chrono::seconds(2));
  if (!report_.sonar_exit) report_.sonar_exit = sonar_->stop(std::chrono::seconds(2));
  report_.sonar_summary = sonar_summary(o_.sonar_dir, report_.sonar_exit);
}

void RunSession::Run::finish_report() {
  report_.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start_).count();
  report_.primitive_calls = tactical_->calls();
  report_.sim_time_s = report_.result ? report_.result->sim_time_s : tactical_->sim_time_s();
  // What the embedded vehicle did after we last heard from it.
  const double last_heard_s = tactical_->sim_time_s();
  for (const auto& line : vehicle_log_) {
    if (std::strtod(line.c_str(), nullptr) > last_heard_s + 1e-9) note("vehicle: " + line);
  }
  if (sim_) {
    report_.final_depth_m = sim_->heave().depth_m;
    report_.final_time_s = sim_->time_s();
    report_.vehicle_watchdog_tripped = sim_->watchdog_tripped();
  }
  std::optional<StopRequest> stop;
  {
    std::lock_guard lock(session_.mutex_);
    stop = session_.stop_;
  }
  const MissionResult* r = report_.result ? &*report_.result : nullptr;
  if (!r) {
    // The executor never told its end: a bug.
    report_.exit_code = kExitInternal;
    return;
  }
  report_.link_lost = report_.link_lost || link_error(*r);
  if (stop && r->outcome == Outcome::Failed && r->reason == stop->reason) {
    report_.stopped_by = stop->who;
    report_.exit_code = stop->exit_code;
  } else {
    report_.exit_code = r->outcome == Outcome::Completed ? kExitOk : kExitAbort;
  }
  if (internal_error_) report_.exit_code = kExitInternal;
}

void RunSession::Run::write_end_of_log() {
  if (!log_) return;
  if (sim_) {
    log_->write({{"event", "vehicle_final"},
                 {"depth_m", tactical::log_time(sim_->heave().depth_m)},
                 {"watchdog_tripped", sim_->watchdog_tripped()},
                 {"sim_time", tactical::log_time(sim_->time_s())}});
  } else if (report_.last_telemetry && report_.last_telemetry->depth_m) {
    // A vehicle of its own: its last word is its last telemetry.
    log_->write({{"event", "vehicle_final"},
                 {"depth_m", tactical::log_time(*report_.last_telemetry->depth_m)},
                 {"from", "telemetry"},
                 {"sim_time", tactical::log_time(report_.last_telemetry->sim_time_s)}});
  }
  nlohmann::ordered_json end;
  end["event"] = "mission_end";
  const MissionResult& r = *report_.result;
  end["outcome"] = strategic::to_string(r.outcome);
  end["exit"] = r.exit;
  end["reason"] = r.reason;
  if (!report_.stopped_by.empty()) end["stopped_by"] = report_.stopped_by;
  if (report_.emergency_shutdown) {
    end["safe_end"] = {{"surface_commanded", report_.emergency_surface},
                       {"surfaced", report_.emergency_surfaced},
                       {"done_answered", report_.shutdown_error.empty()},
                       {"cut_short", report_.hurried}};
  }
  end["exit_code"] = report_.exit_code;
  // When the mission's executor ended; sim_time is the end of the whole run
  // (after the safe end), so that times in the log never go back.
  end["mission_sim_time"] = tactical::log_time(r.sim_time_s);
  end["sim_time"] = tactical::log_time(std::max({r.sim_time_s, tactical_->sim_time_s(), sim_ ? sim_->time_s() : 0.0}));
  log_->write(end);
  if (auto s = log_->status(); !s) {
    err_ << "strata run: the mission log is incomplete: " << s.error().message << "\n";
    report_.exit_code = kExitIo;
  }
  report_.log_lines = log_->lines();
  log_.reset();  // closed and flushed
}

}  // namespace strata::run
