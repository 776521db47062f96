#include "run/session_run.h"

#include <fmt/format.h>

#include "core/exit_codes.h"
#include "run/inputs.h"
#include "tactical/execution_level.h"
#include "strategic/coral_engine.h"
#include "strategic/prolog_executor.h"

namespace strata::run {

using namespace detail;

Stage RunSession::Run::load_inputs() {
  Stage loaded = session_.load();
  if (loaded) report_.mission_name = loaded_.name;
  return loaded;
}

Stage RunSession::Run::open_log() {
  report_.log_dated = o_.log.empty() && !o_.log_dir.empty() && !o_.log_stream;
  if (o_.log.empty() && o_.log_dir.empty() && !o_.log_stream) return {};
  auto opened = o_.log_stream    ? tactical::MissionLog::to_stream(*o_.log_stream, run_info(o_, loaded_))
                : o_.log.empty() ? tactical::MissionLog::open_dated(o_.log_dir, o_.mission, run_info(o_, loaded_))
                                 : tactical::MissionLog::open(o_.log, run_info(o_, loaded_));
  if (!opened)
    return Error{ErrorKind::LogUnwritable, "", "cannot write the mission log: " + opened.error().message, {}};
  log_ = std::move(opened.value());
  report_.log_path = o_.log_stream ? o_.log : log_->path();
  // A runaway mission ends at the log's bound, as at any limit: from
  // whatever thread writes the line (RunSession::stop interrupts the rules).
  log_->limit(o_.max_log_bytes, [this] {
    session_.stop(
        "limit",
        fmt::format("the mission log reached its limit of {} MB (--max-log-mb sets it)", o_.max_log_bytes >> 20),
        kExitAbort);
  });
  if (o_.seed) log_->write({{"event", "choice"}, {"seed", *o_.seed}});
  if (loaded_.verification) {
    log_->write(verification_record(*loaded_.verification, o_.unverified || loaded_.answers.has_value()));
  }
  if (loaded_.answers) {
    const AnswerScript& a = *loaded_.answers;
    log_->write(
        {{"event", "answers"}, {"file", a.path}, {"answers", a.answers.size()}, {"net", a.net}, {"from", a.from}});
  }
  return {};
}

Stage RunSession::Run::open_vehicle() {
  if (tactical::execution_level_of(o_.vehicle) == tactical::ExecutionLevel::Imc) return {};  // connect_imc()
  if (!o_.vehicle.empty()) {
    auto endpoint = parse_listen(o_.vehicle);
    if (!endpoint) return Error{ErrorKind::Usage, "--vehicle", endpoint.error().message, {}};
    link_options_.host = endpoint.value().first;
    link_options_.port = endpoint.value().second;
    if (link_options_.port == 0) return Error{ErrorKind::Usage, "", "--vehicle needs a port (HOST:PORT)", {}};
    return {};
  }
  sim_.emplace(loaded_.params, loaded_.scenario);
  vehicle::ServerOptions so;
  so.clock = o_.realtime ? protocol::ClockMode::Wall : protocol::ClockMode::Lockstep;
  so.speed = o_.speed;
  if (!o_.realtime) so.lockstep_silence_s = 0.0;
  // The embedded vehicle's own log ("6.0 s: watchdog: ..."). What it says
  // while the link works also reaches us as protocol events, so these are
  // kept and shown only for the time after we last heard from it.
  so.log = [this](const std::string& line) { vehicle_log_.push_back(line); };
  server_ = std::make_unique<vehicle::VehicleServer>(io_, *sim_, so);
  // The two levels talk the same protocol as over TCP, through a pair of
  // local sockets: no TCP stack for every line (about a quarter of a
  // campaign's CPU time went to it), and no port another process could reach.
  asio::local::stream_protocol::socket ours(io_), theirs(io_);
  asio::error_code ec;
  asio::local::connect_pair(ours, theirs, ec);
  if (ec) {
    return Error{ErrorKind::VehicleUnavailable, "", "cannot connect to the simulated vehicle: " + ec.message(), {}};
  }
  if (auto r = server_->start_paired(std::move(theirs)); !r) {
    return Error{ErrorKind::VehicleUnavailable, "", "cannot start the simulated vehicle: " + r.error().message, {}};
  }
  paired_.emplace(std::move(ours));
  // In lockstep simulated time decides every timeout (the link's bounded
  // advances; the vehicle's watchdog in simulated time when the link is
  // lost): neither end counts wall time, so neither a loaded machine nor a
  // rule that blocks for a while can change a run. The vehicle is in this
  // process; the run's end closes the link, which trips its watchdog.
  return {};
}

Stage RunSession::Run::connect() {
  if (tactical::execution_level_of(o_.vehicle) == tactical::ExecutionLevel::Imc) return connect_imc();
  link_options_.tap = o_.wire_tap;
  auto link = tactical::VehicleLink::create(io_, link_options_);
  link_ = link;
  std::optional<core::Result<protocol::Welcome>> welcome;
  auto answered = [&](core::Result<protocol::Welcome> w) { welcome = std::move(w); };
  if (paired_) {
    link->connect_paired(std::move(*paired_), answered);
    paired_.reset();
  } else {
    link->connect(answered);
  }
  while (!welcome && io_.run_one() > 0) {}
  if (!welcome || !welcome->ok()) {
    return Error{ErrorKind::VehicleUnavailable,
                 "",
                 welcome ? welcome->error().message : std::string("the vehicle link ended before hello"),
                 {}};
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
  const std::string where =
      o_.vehicle.empty() ? "in this process" : fmt::format("at {}:{}", link_options_.host, link_options_.port);
  note(fmt::format("vehicle {} {} ({}{})", w.vehicle_name, where, report_.lockstep ? "lockstep" : "wall clock",
                   o_.vehicle.empty() ? embedded_world() : ""));
  return {};
}

// ", embedded; open water, scenario nominal from missions/survey/scenarios/
// nominal.toml": which world the run is in, and why.
std::string RunSession::Run::embedded_world() const {
  const std::string name = scenario_name(o_);
  const std::string& origin = loaded_.scenario_origin;
  const char* world = loaded_.scenario.world.open_water ? "open water" : "the tank";
  if (origin == name) return fmt::format(", embedded; {}, scenario {}", world, name);
  return fmt::format(", embedded; {}, scenario {} {}{}", world, name, origin.starts_with("built in") ? "" : "from ",
                     origin);
}

Stage RunSession::Run::connect_imc() {
  if (!o_.sonar_dir.empty()) {
    return Error{ErrorKind::Usage,
                 "",
                 "--sonar needs the Phoenix protocol's sonar socket; an IMC vehicle has none (docs/imc.md)",
                 {}};
  }
  auto options = tactical::parse_imc_vehicle(o_.vehicle);
  if (!options) return Error{ErrorKind::Usage, "--vehicle", options.error().message, {}};
  // --speed: how much faster than real time the vehicle runs (a simulated
  // one: `strata vehicle --imc --speed K`). The FollowReference timeout is
  // 10 s of the vehicle's clock on DUNE; here it is 10 wall seconds, so a
  // busy machine's pause does not end a fast vehicle's plan.
  // Capped at a minute of the vehicle's clock: a command line reused from a
  // simulation must not leave a real vehicle following a dead controller for
  // hours.
  options.value().follow_timeout_s = std::min(60.0, 10.0 * std::max(1.0, o_.speed));
  imc_ = tactical::ImcLink::create(io_, options.value());
  link_ = imc_;
  std::optional<core::Result<tactical::ImcVehicleInfo>> heard;
  imc_->connect([&](core::Result<tactical::ImcVehicleInfo> v) { heard = std::move(v); });
  while (!heard && io_.run_one() > 0) {}
  if (!heard || !heard->ok()) {
    return Error{ErrorKind::VehicleUnavailable,
                 "",
                 heard ? heard->error().message : std::string("the IMC link ended before the vehicle answered"),
                 {}};
  }
  const tactical::ImcVehicleInfo& v = heard->value();
  report_.lockstep = false;
  report_.execution_level = "imc";
  if (log_) {
    log_->write({{"event", "vehicle"},
                 {"name", v.name},
                 {"clock", "vehicle"},
                 {"embedded", false},
                 {"execution_level", "imc"},
                 {"imc_id", v.id}});
  }
  note(
      fmt::format("vehicle {} (IMC id 0x{:04X}) at {} (IMC over UDP, the vehicle's clock; plan '{}' started from "
                  "udp://{}:{})",
                  v.name, v.id, o_.vehicle, imc_->plan_id(), imc_->bind_address(), imc_->local_port()));
  return {};
}

Stage RunSession::Run::start_sonar() {
  if (o_.sonar_dir.empty()) return {};
  auto started =
      start_sonar_manager(o_.sonar_dir, link_options_.host, sonar_port_, io_, server_ ? server_->sonar() : nullptr);
  if (!started) return input_error(started.error(), "--sonar");
  sonar_.emplace(std::move(started).value());
  note(fmt::format("sonar manager: pid {}, scans in {}", sonar_->pid(), o_.sonar_dir));
  if (log_) log_->write({{"event", "sonar_manager"}, {"dir", o_.sonar_dir}});
  return {};
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
    for (RunObserver* obs : session_.observers_) obs->vehicle_event(e.text, e.sim_time_s);
  });
  tactical_->on_call([this](const tactical::CallRecord& c) {
    if (o_.trace) report_.trace.push_back(c);
    if (c.primitive == kShutdown && c.value == true && !safe_end_running_) mission_sent_done_ = true;
    // An exec or ood answered 0: what the vehicle said meanwhile is its reason.
    if (!c.vehicle_said.empty()) report_.vehicle_reason = c.vehicle_said;
    check_limits();
  });
  if (o_.telemetry_hz > 0) {
    link_->send(protocol::make_telemetry(0, o_.telemetry_hz), [](const core::Result<protocol::VehicleMessage>&) {});
  }
  tactics_.emplace(*tactical_);
  strategic::Tactics* tactics = &*tactics_;
  if (loaded_.answers) {
    scripted_ = std::make_unique<ScriptedTactics>(
        *tactics_, io_, *loaded_.answers, log_ ? &*log_ : nullptr, [this](const std::string& why) {
          stop_here("answers", "the run left the scripted answers: " + why, kExitInvalid);
        });
    tactics = scripted_.get();
    note(fmt::format("answers: {} scripted from {}{}", loaded_.answers->answers.size(), loaded_.answers->path,
                     loaded_.answers->from.empty() ? "" : " (" + loaded_.answers->from + ")"));
  }
  std::unique_ptr<strategic::Executor> executor;
  if (loaded_.program) {
    strategic::EngineOptions engine_options;
    engine_options.seed = o_.seed;
    executor = std::make_unique<strategic::CoralEngine>(*loaded_.program, *tactics, engine_options);
  } else {
    strategic::PrologOptions prolog_options;
    prolog_options.inference_limit = o_.inference_limit;
    executor = std::make_unique<strategic::PrologExecutor>(*loaded_.rules, *tactics, loaded_.catalogue, prolog_options);
  }
  {
    std::lock_guard lock(session_.mutex_);  // stop() reads executor_ from another thread
    executor_ = std::move(executor);
  }
  if (scripted_) executor_->add_observer(*scripted_);
  if (log_) {
    log_observer_.emplace(*log_);
    executor_->add_observer(*log_observer_);
  }
  phase_recorder_.emplace(report_.phases);
  executor_->add_observer(*phase_recorder_);
  for (RunObserver* obs : session_.observers_) executor_->add_observer(*obs);
  // The vehicle itself, not the scripted answers in front of it.
  safe_end_.emplace(*tactics_, loaded_.catalogue, [this](const std::string& text) { note(text); });
  link_->on_lost([this](const core::Error& e) {
    report_.link_lost = true;
    report_.link_lost_why = e.message;
    if (executor_->running()) executor_->cancel(fmt::format("lost the link to the vehicle: {}", e.message));
  });
  link_->on_fault([this](const std::string& why) {
    // The vehicle no longer takes this run's commands: the mission cannot go
    // on; the safe end still tries to surface it.
    report_.vehicle_fault = why;
    if (log_)
      log_->write(
          {{"event", "vehicle_fault"}, {"reason", why}, {"sim_time", tactical::log_time(tactical_->sim_time_s())}});
    if (executor_->running()) executor_->cancel(fmt::format("the vehicle: {}", why));
  });
}

}  // namespace strata::run
