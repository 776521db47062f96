#include "run/session.h"

#include "run/session_run.h"

#include <algorithm>
#include <cstdlib>
#include <exception>

#include "core/exit_codes.h"

namespace strata::run {
namespace {

using strategic::MissionResult;
using strategic::Outcome;
using namespace detail;

}  // namespace

RunSession::RunSession(RunOptions options) : options_(std::move(options)), loaded_(std::make_unique<LoadedMission>()) {}
RunSession::~RunSession() = default;

void RunSession::add_observer(RunObserver& observer) { observers_.push_back(&observer); }

std::string_view to_string(StopMode mode) {
  switch (mode) {
    case StopMode::Interrupt: return "interrupt";
    case StopMode::Abort: return "abort";
    case StopMode::Hard: return "hard";
  }
  return "interrupt";
}

void RunSession::stop(const std::string& who, const std::string& reason, int exit_code, StopMode mode) {
  std::lock_guard lock(mutex_);
  ++stop_requests_;
  if (mode == StopMode::Hard) hard_requested_ = true;
  if (!stop_) stop_ = StopRequest{who, reason, exit_code, mode};
  if (!active_) return;
  Run* run = active_;
  asio::post(run->io(), [run] { run->on_stop(); });
  run->interrupt(stop_->reason);
}

core::Result<void, Error> RunSession::load() {
  if (!load_result_) {
    load_started_ = std::chrono::steady_clock::now();
    load_result_ = load_mission(options_, *loaded_);
  }
  return *load_result_;
}

RunReport RunSession::run() {
  Run run(*this);
  return run.execute();
}

RunReport RunSession::Run::execute() {
  report_.lockstep = !o_.realtime;
  Stage stage = load_inputs();
  if (stage) stage = open_log();
  if (stage) stage = open_vehicle();
  if (stage) {
    std::lock_guard lock(session_.mutex_);
    session_.active_ = this;
  }
  if (stage) stage = connect();
  if (stage) stage = start_sonar();
  if (stage) {
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
  if (!stage) {
    report_.error = stage.error();
    for (RunObserver* obs : session_.observers_) obs->run_ended(report_);
    return report_;
  }
  close_sonar();
  finish_report();
  write_end_of_log();
  for (RunObserver* obs : session_.observers_) obs->run_ended(report_);
  return report_;
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
  bool hard = false;
  {
    std::lock_guard lock(session_.mutex_);
    stop = session_.stop_;
    requests = session_.stop_requests_;
    hard = session_.hard_requested_;
  }
  if (!stop || finished_ || !executor_) return;
  if (executor_->running()) {
    executor_->cancel(stop->reason);
  } else if ((requests > 1 || hard) && safe_end_running_) {
    report_.hurried = true;
    safe_end_->abandon();
  } else if ((requests > 1 || hard) && settling_ && server_) {
    // Waiting for the embedded vehicle to surface by itself: stop waiting.
    report_.hurried = true;
    server_->stop();
  }
}

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
  // Lockstep, and an IMC vehicle (its messages' clock); not a wall-clock run.
  if ((!report_.lockstep && !imc_) || !executor_ || !executor_->running()) return;
  if (tactical_->sim_time_s() > o_.max_sim_time_s) {
    stop_here("limit",
              fmt::format("the simulated-time limit was reached ({:.0f} s; --max-sim-time sets it)", o_.max_sim_time_s),
              kExitAbort);
  }
}

bool RunSession::Run::needs_safe_end(const MissionResult& r) const {
  if (r.outcome == Outcome::Completed) return false;
  // The mission's own abort path ran to Figure 10's `done`: nothing to add.
  if (mission_sent_done_) return false;
  return link_->connected() && safe_end_->possible();
}

void RunSession::Run::mission_ended(const MissionResult& ended) {
  std::optional<StopRequest> stop;
  bool hard = false;
  {
    std::lock_guard lock(session_.mutex_);
    stop = session_.stop_;
    hard = session_.hard_requested_;
  }
  MissionResult r = ended;
  // The executor ended because of the stop: the stop says what it was.
  if (stop && r.outcome == Outcome::Failed && r.reason == stop->reason) {
    report_.stop_mode = std::string(to_string(hard ? StopMode::Hard : stop->mode));
    if (stop->mode == StopMode::Abort && !hard) r.outcome = Outcome::Aborted;
  }
  report_.result = r;
  if (report_.stop_mode == "hard") {
    note("hard stop: the vehicle is neither surfaced nor sent done; it is left to its own watchdog", r.sim_time_s);
    if (log_) log_->write({{"event", "hard_stop"}, {"sim_time", tactical::log_time(r.sim_time_s)}});
    wrap_up();
    return;
  }
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
    if (imc_ && report_.emergency_surface) report_.surface_method = std::string(imc_->surface_method());
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
  // The vehicle hears of it now, not when it next reads the socket: if the
  // mission left it under water with its network up, its watchdog surfaces
  // it before the run ends.
  server_->controller_gone();
  bool hard = false;
  {
    std::lock_guard lock(session_.mutex_);
    hard = session_.hard_requested_;
  }
  if (hard) {
    // A hard stop stops now: nothing waits for the vehicle, not even its
    // own watchdog's surfacing.
    server_->stop();
    finished_ = true;
    return;
  }
  settling_ = true;
  server_->when_settled([this] {
    settling_ = false;
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
  const double last_heard_s = tactical_->last_heard_s();
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
  if (imc_) report_.imc_dropped = tactical::imc_summary(imc_->counts());
  if (stop && r->outcome != Outcome::Completed && r->reason == stop->reason) {
    report_.stopped_by = stop->who;
    report_.exit_code = stop->exit_code;
  } else {
    report_.exit_code = r->outcome == Outcome::Completed ? kExitOk : kExitAbort;
  }
  if (internal_error_) report_.exit_code = kExitInternal;
  if (scripted_) {
    report_.answers_used = scripted_->used();
    report_.answers_total = scripted_->total();
    report_.answers_diverged = scripted_->diverged();
    report_.answers_first_unused = scripted_->first_unused();
    if (report_.answers_diverged.empty() && report_.answers_used < report_.answers_total) {
      note(fmt::format("answers: the run ended before the script did: {} of {} answers used; the first not used: {}",
                       report_.answers_used, report_.answers_total, report_.answers_first_unused));
    } else if (report_.answers_diverged.empty()) {
      note(fmt::format("answers: all {} scripted answers used", report_.answers_total));
    }
  }
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
  if (scripted_) {
    nlohmann::ordered_json a{{"event", "answers_end"}, {"used", scripted_->used()}, {"of", scripted_->total()}};
    if (!scripted_->diverged().empty()) a["diverged"] = scripted_->diverged();
    if (!report_.answers_first_unused.empty()) a["first_unused"] = report_.answers_first_unused;
    log_->write(a);
  }
  nlohmann::ordered_json end;
  end["event"] = "mission_end";
  const MissionResult& r = *report_.result;
  end["outcome"] = strategic::to_string(r.outcome);
  end["exit"] = r.exit;
  end["reason"] = r.reason;
  if (!report_.stopped_by.empty()) end["stopped_by"] = report_.stopped_by;
  if (!report_.stop_mode.empty()) end["stop"] = report_.stop_mode;
  if (report_.emergency_shutdown) {
    end["safe_end"] = {{"surface_commanded", report_.emergency_surface},
                       {"surfaced", report_.emergency_surfaced},
                       {"done_answered", report_.shutdown_error.empty()},
                       {"cut_short", report_.hurried}};
    // IMC: a z = 0 Reference, or an Abort when the vehicle took no Reference.
    if (!report_.surface_method.empty()) end["safe_end"]["surface_by"] = report_.surface_method;
  }
  if (!report_.vehicle_fault.empty()) end["vehicle_fault"] = report_.vehicle_fault;
  if (imc_) end["imc"] = tactical::imc_counts_json(imc_->counts());
  end["exit_code"] = report_.exit_code;
  // When the mission's executor ended; sim_time is the end of the whole run
  // (after the safe end), so that times in the log never go back.
  end["mission_sim_time"] = tactical::log_time(r.sim_time_s);
  end["sim_time"] = tactical::log_time(std::max({r.sim_time_s, tactical_->sim_time_s(), sim_ ? sim_->time_s() : 0.0}));
  log_->write(end);
  if (auto s = log_->status(); !s) {
    report_.log_error = Error{ErrorKind::LogUnwritable, "", "the mission log is incomplete: " + s.error().message, {}};
  }
  report_.log_lines = log_->lines();
  report_.log_dropped = log_->dropped();
  log_.reset();  // closed and flushed
}

}  // namespace strata::run
