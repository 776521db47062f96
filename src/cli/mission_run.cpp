#include "cli/mission_run.h"

#include <chrono>
#include <cstdlib>
#include <csignal>
#include <filesystem>
#include <memory>

#include <asio.hpp>
#include <fmt/format.h>

#include "cli/commands.h"
#include "cli/console.h"
#include "cli/coral_load.h"
#include "cli/emergency.h"
#include "cli/exit_codes.h"
#include "cli/sonar_child.h"
#include "coral/compiler.h"
#include "coral/verify_report.h"
#include "prolog/mission.h"
#include "strategic/coral_engine.h"
#include "strategic/log_observer.h"
#include "strategic/prolog_executor.h"
#include "tactical/mission_data.h"
#include "tactical/mission_log.h"
#include "tactical/sha256.h"
#include "tactical/tactical_level.h"
#include "tactical/vehicle_link.h"
#include "vehicle/params.h"
#include "vehicle/server.h"

namespace strata::cli {
namespace {

namespace fs = std::filesystem;
using strategic::MissionResult;
using strategic::Outcome;

constexpr const char* kVersion = "0.1.0";
constexpr const char* kInterrupted = "interrupted by the operator";
// Lockstep: wall seconds allowed per simulated second of a call (>= 100x real time).
constexpr double kLockstepWallPerSim = 0.01;

std::string sha256_or_empty(const std::string& path) {
  auto r = tactical::sha256_file(path);
  return r ? r.value() : std::string();
}

struct LoadedMission {
  core::SourceManager sources;
  std::optional<coral::Program> program;   // a .coral mission
  std::unique_ptr<prolog::Mission> rules;  // a .pl mission
  std::string name;                        // the mission net's name, or the rules' file stem
  std::string data_file;                   // as the mission names it, resolved; "" none
};

// Compiles the mission; diagnostics (warnings too) go to err.
int load_coral(const std::string& path, const tactical::Catalogue& catalogue, LoadedMission& loaded,
               std::ostream& err) {
  CoralLoad load = load_coral_file(path, catalogue, err, "strata run", "; not running");
  if (!load.program) return load.exit_code;
  if (!load.program->mission) {
    err << fmt::format("{}: error: no `mission` net to run (the file holds only phase nets)\n", path);
    return kExitInvalid;
  }
  loaded.sources = std::move(load.sources);
  loaded.program = std::move(load.program);
  const coral::CompiledNet& mission = loaded.program->nets[*loaded.program->mission];
  loaded.name = mission.name;
  loaded.data_file = mission.data_file;
  return kExitOk;
}

// Loads and checks the rules; messages (warnings too) go to err.
int load_prolog(const std::string& path, const tactical::Catalogue& catalogue, LoadedMission& loaded,
                std::ostream& err) {
  std::vector<prolog::Message> messages;
  auto rules = prolog::Mission::load(path, catalogue, messages);
  for (const auto& m : messages) err << prolog::format_message(m) << "\n";
  if (!rules) {
    err << "strata run: " << rules.error().message << "; not running\n";
    return exit_code_for_input(rules.error());
  }
  loaded.rules = std::move(rules.value());
  loaded.name = loaded.rules->name();
  loaded.data_file = loaded.rules->data_file();
  return kExitOk;
}

// What the log keeps of the verification: whether it passed, and each
// property that did not hold, with its message.
nlohmann::json verification_record(const coral::VerifyReport& v, bool unverified) {
  nlohmann::json failed = nlohmann::json::array();
  std::uint64_t states = 0;
  for (const auto& n : v.nets) {
    states += n.states;
    for (const auto& p : n.properties) {
      if (p.status == coral::Property::Status::Holds) continue;
      failed.push_back({{"net", n.name}, {"property", p.key}, {"status", coral::status_name(p.status)},
                        {"message", p.message}});
    }
  }
  nlohmann::json j{{"event", "verification"}, {"ok", v.ok()}, {"nets", v.nets.size()}, {"states", states}};
  if (!v.ok()) {
    j["failed"] = std::move(failed);
    j["run_anyway"] = unverified;
  }
  return j;
}

std::string format_wall(double seconds) {
  return seconds < 1.0 ? fmt::format("{:.0f} ms", seconds * 1000.0) : fmt::format("{:.2f} s", seconds);
}

}  // namespace

void RunControl::cancel(const std::string& reason) {
  std::lock_guard lock(mutex_);
  if (cancel_) cancel_(reason);
}

// Attaches a run's cancel to a RunControl for as long as it lives.
struct RunControlAttachment {
  RunControlAttachment(RunControl* c, std::function<void(const std::string&)> cancel) : control(c) {
    if (!control) return;
    std::lock_guard lock(control->mutex_);
    control->cancel_ = std::move(cancel);
  }
  ~RunControlAttachment() {
    if (!control) return;
    std::lock_guard lock(control->mutex_);
    control->cancel_ = nullptr;
  }
  RunControlAttachment(const RunControlAttachment&) = delete;
  RunControlAttachment& operator=(const RunControlAttachment&) = delete;
  RunControl* control;
};

RunReport run_mission(const RunOptions& o, std::ostream& out, std::ostream& err) {
  RunReport report;
  auto wall_start = std::chrono::steady_clock::now();
  auto fail = [&](int code) {
    report.exit_code = code;
    return report;
  };

  // ---- inputs ---------------------------------------------------------------
  const auto extension = fs::path(o.mission).extension();
  if (extension != ".coral" && extension != ".pl") {
    err << fmt::format("strata run: '{}': a mission is a .coral file (CORAL) or a .pl file (PROLOG)\n",
                       o.mission);
    return fail(kExitUsage);
  }
  auto catalogue = load_catalogue_option(o.catalogue);
  if (!catalogue) {
    err << "strata run: " << catalogue.error().message << "\n";
    return fail(exit_code_for_input(catalogue.error()));
  }
  LoadedMission loaded;
  if (int code = extension == ".pl" ? load_prolog(o.mission, catalogue.value(), loaded, err)
                                    : load_coral(o.mission, catalogue.value(), loaded, err);
      code != kExitOk) {
    return fail(code);
  }

  // CORAL: verify the nets before anything moves.
  std::optional<coral::VerifyReport> verification;
  if (loaded.program) {
    coral::VerifyOptions vo;
    vo.mission_only = true;  // what this run can reach
    verification = coral::verify_program(*loaded.program, vo);
    if (!verification->ok()) {
      err << coral::verify_failures_text(*verification);
      if (!o.unverified) {
        err << fmt::format("strata run: {} fails verification; not running (`strata verify {}` shows every "
                           "property; --unverified runs it anyway, and its log records that)\n",
                           o.mission, o.mission);
        return fail(kExitInvalid);
      }
      err << "strata run: warning: running a mission that fails verification (--unverified)\n";
    }
  }

  vehicle::VehicleParams params = vehicle::default_params();
  if (!o.params.empty()) {
    auto p = vehicle::load_params(o.params);
    if (!p) {
      err << "strata run: " << p.error().message << "\n";
      return fail(exit_code_for_input(p.error()));
    }
    params = p.value();
  }

  std::string data_path = !o.data.empty() ? o.data : loaded.data_file;
  std::optional<tactical::MissionData> data;
  if (!data_path.empty()) {
    auto d = tactical::MissionData::load(data_path, tactical::DataLimits{params.tank_depth_m});
    if (!d) {
      err << "strata run: " << d.error().message << "\n";
      return fail(exit_code_for_input(d.error()));
    }
    data = std::move(d.value());
  }
  std::optional<tactical::DataCursor> cursor;
  if (data) cursor.emplace(*data);

  auto scenario = load_scenario_option(o.scenario, o.mission);
  if (!scenario) {
    err << "strata run: " << scenario.error().message << "\n";
    return fail(exit_code_for_input(scenario.error()));
  }
  const bool embedded = o.vehicle.empty();
  if (!embedded && (!o.scenario.empty() || !o.params.empty() || o.realtime)) {
    err << "strata run: --scenario, --params and --realtime set up the embedded vehicle; with "
           "--vehicle they belong to that vehicle's own command line\n";
    return fail(kExitUsage);
  }

  std::optional<tactical::MissionLog> log;
  if (!o.log.empty()) {
    tactical::RunInfo info;
    info.version = kVersion;
    info.mission = o.mission;
    info.mission_sha256 = sha256_or_empty(o.mission);
    info.data = data_path;
    if (!data_path.empty()) info.data_sha256 = sha256_or_empty(data_path);
    info.scenario = embedded ? (o.scenario.empty() ? "nominal" : o.scenario) : "external";
    info.seed = embedded ? scenario.value().seed : 0;
    info.clock = o.realtime ? "wall" : "lockstep";
    auto opened = tactical::MissionLog::open(o.log, info);
    if (!opened) {
      err << "strata run: cannot write the mission log: " << opened.error().message << "\n";
      return fail(kExitIo);
    }
    log = std::move(opened.value());
    if (o.seed) log->write({{"event", "choice"}, {"seed", *o.seed}});
    if (verification) log->write(verification_record(*verification, o.unverified));
  }

  // ---- the vehicle ----------------------------------------------------------
  asio::io_context io;
  Console console(out, o.tty);
  std::vector<std::string> vehicle_log;
  std::optional<vehicle::Simulation> sim;
  std::unique_ptr<vehicle::VehicleServer> server;
  tactical::LinkOptions link_options;
  if (embedded) {
    sim.emplace(params, scenario.value());
    vehicle::ServerOptions so;
    so.clock = o.realtime ? protocol::ClockMode::Wall : protocol::ClockMode::Lockstep;
    so.speed = o.speed;
    // The embedded vehicle's own log ("6.0 s: watchdog: ..."). What it says
    // while the link works also reaches us as protocol events, so these are
    // kept and shown only for the time after we last heard from it.
    so.log = [&vehicle_log](const std::string& line) { vehicle_log.push_back(line); };
    server = std::make_unique<vehicle::VehicleServer>(io, *sim, so);
    if (auto r = server->start(); !r) {
      err << "strata run: cannot start the simulated vehicle: " << r.error().message << "\n";
      return fail(kExitIo);
    }
    link_options.port = server->port();
    // In lockstep the vehicle answers within microseconds: a second of
    // silence is a lost link, not a slow vehicle.
    if (!o.realtime) link_options.reply_timeout = std::chrono::milliseconds(1000);
  } else {
    auto endpoint = parse_listen(o.vehicle);
    if (!endpoint) {
      err << "strata run: --vehicle: " << endpoint.error().message << "\n";
      return fail(kExitUsage);
    }
    link_options.host = endpoint.value().first;
    link_options.port = endpoint.value().second;
  }
  if (link_options.port == 0) {
    err << "strata run: --vehicle needs a port (HOST:PORT)\n";
    return fail(kExitUsage);
  }

  link_options.tap = o.wire_tap;
  auto link = tactical::VehicleLink::create(io, link_options);
  std::optional<core::Result<protocol::Welcome>> welcome;
  link->connect([&](core::Result<protocol::Welcome> w) { welcome = std::move(w); });
  while (!welcome && io.run_one() > 0) {
  }
  if (!welcome || !welcome->ok()) {
    err << "strata run: "
        << (welcome ? welcome->error().message : std::string("the vehicle link ended before hello"))
        << "\n";
    return fail(kExitIo);
  }
  const bool lockstep = welcome->value().clock == protocol::ClockMode::Lockstep;
  if (log) {
    // The vehicle's own word on its clock (the header says what was asked).
    // No address: the port is chosen at random and the log must not vary.
    log->write({{"event", "vehicle"},
                {"name", welcome->value().vehicle_name},
                {"clock", lockstep ? "lockstep" : "wall"},
                {"embedded", embedded}});
  }
  console.line(fmt::format("vehicle {} at {}:{} ({}{}{})", welcome->value().vehicle_name,
                           link_options.host, link_options.port, lockstep ? "lockstep" : "wall clock",
                           embedded ? ", embedded" : "",
                           embedded ? fmt::format(", scenario {}",
                                                  o.scenario.empty() ? "nominal" : o.scenario)
                                    : ""));

  // ---- the Sonar Manager ---------------------------------------------------------
  std::optional<SonarChild> sonar;
  if (!o.sonar_dir.empty()) {
    auto started = start_sonar_manager(o.sonar_dir, link_options.host, welcome->value().sonar_port, io,
                                       server ? server->sonar() : nullptr);
    if (!started) {
      err << "strata run: --sonar: " << started.error().message << "\n";
      return fail(exit_code_for_input(started.error()));
    }
    sonar.emplace(std::move(started).value());
    console.line(fmt::format("sonar manager: pid {}, scans in {}", sonar->pid(), o.sonar_dir));
    if (log) log->write({{"event", "sonar_manager"}, {"dir", o.sonar_dir}});
  }

  // ---- the Tactical and Strategic levels --------------------------------------
  tactical::TacticalLevel tactical(io, catalogue.value(), link, cursor ? &*cursor : nullptr,
                                   log ? &*log : nullptr);
  // Wall clock: a call may take its simulated time divided by the speed.
  // Lockstep: the vehicle computes a call's simulated time as fast as it
  // can; allow for at least 100x real time (a 1 h sleep may take 36 s of
  // wall time on a slow machine) on top of the link's own timeout.
  tactical.set_wall_seconds_per_sim_second(lockstep ? kLockstepWallPerSim : 1.0 / o.speed);
  tactical.on_report([&](const std::string& text, double t) {
    console.report(text, t);
    if (o.on_report) o.on_report(text, t);
  });
  tactical.on_telemetry([&](const protocol::Telemetry& t) {
    console.telemetry(t);
    if (o.on_telemetry) o.on_telemetry(t);
  });
  tactical.on_vehicle_event([&](const protocol::Event& e) { console.vehicle_event(e.text, e.sim_time_s); });
  if (o.telemetry_hz > 0) {
    link->send(protocol::make_telemetry(0, o.telemetry_hz), [](core::Result<protocol::VehicleMessage>) {});
  }

  if (o.trace) tactical.on_call([&report](const tactical::CallRecord& c) { report.trace.push_back(c); });

  strategic::TacticalTactics tactics(tactical);
  std::unique_ptr<strategic::Executor> executor;
  if (loaded.program) {
    strategic::EngineOptions engine_options;
    engine_options.seed = o.seed;
    executor = std::make_unique<strategic::CoralEngine>(*loaded.program, tactics, engine_options);
  } else {
    strategic::PrologOptions prolog_options;
    prolog_options.inference_limit = o.inference_limit;
    executor = std::make_unique<strategic::PrologExecutor>(*loaded.rules, tactics, catalogue.value(),
                                                           prolog_options);
  }
  strategic::Executor& engine = *executor;
  engine.add_observer(console);
  std::optional<strategic::LogObserver> log_observer;
  if (log) {
    log_observer.emplace(*log);
    engine.add_observer(*log_observer);
  }
  for (strategic::Observer* extra : o.observers) engine.add_observer(*extra);
  // Declared after the engine, so it detaches before the engine goes.
  RunControlAttachment control(o.control.get(), [&](const std::string& why) {
    asio::post(io, [&engine, why] { engine.cancel(why); });
  });

  bool link_lost = false;
  std::string link_lost_why;
  link->on_lost([&](const core::Error& e) {
    link_lost = true;
    link_lost_why = e.message;
    engine.cancel(fmt::format("lost the link to the vehicle: {}", e.message));
  });

  std::optional<asio::signal_set> signals;
  if (o.handle_signals) {
    signals.emplace(io, SIGINT, SIGTERM);
    signals->async_wait([&](const asio::error_code& e, int) {
      if (e) return;
      signals->clear();  // a second Ctrl-C ends the process at once
      engine.cancel(kInterrupted);
    });
  }

  // After the mission: Figure 10's `done` if the Strategic level could not
  // run its own abort path, then the link closes and an embedded vehicle is
  // left to settle (its watchdog may be surfacing it) before the loop ends.
  // From the mission's end on, Ctrl-C ends the process at once.
  auto release_signals = [&] {
    if (signals) {
      signals->clear();
      signals->cancel();
    }
  };
  bool finished = false;
  auto wrap_up = [&] {
    release_signals();
    link->close();
    if (server) {
      server->when_settled([&] {
        server->stop();
        finished = true;
      });
    } else {
      finished = true;
    }
  };
  Emergency emergency(tactical, catalogue.value(), [&](const std::string& text) { console.line(text); });
  engine.start([&](const MissionResult& result) {
    report.result = result;
    if (result.outcome != Outcome::Failed || !link->connected() || !emergency.possible()) {
      wrap_up();
      return;
    }
    const bool link_gone = result.call_error && (*result.call_error == core::ErrorCode::Timeout ||
                                                 *result.call_error == core::ErrorCode::Closed);
    const std::string plan = emergency.plan(link_gone);
    release_signals();
    console.line(fmt::format("the mission ended without its own abort path; strata run sends {}, as "
                             "Figure 10's done does (Ctrl-C stops at once)",
                             plan),
                 result.sim_time_s);
    if (log) {
      log->write({{"event", "emergency"}, {"action", plan}, {"sim_time", tactical::log_time(result.sim_time_s)}});
    }
    emergency.run(link_gone, [&] {
      report.emergency_shutdown = emergency.shutdown_sent();
      report.emergency_surface = emergency.surface_commanded();
      report.emergency_surfaced = emergency.surfaced();
      wrap_up();
    });
  });
  while (!finished && io.run_one() > 0) {
  }
  // Handlers still queued (a closed socket's last callbacks) run now, before
  // the objects they point at go.
  io.restart();
  io.poll();
  if (sonar) {
    // The vehicle's last pings and its end frame reach the manager, then it
    // writes its last scan and ends. A vehicle of its own (--vehicle) sends
    // no end frame when our run ends: the manager is stopped after a moment
    // and writes what it has.
    drain_sonar(io, server ? server->sonar() : nullptr);
    report.sonar_exit = sonar->wait(server ? std::chrono::seconds(20) : std::chrono::seconds(2));
    if (!report.sonar_exit) report.sonar_exit = sonar->stop(std::chrono::seconds(2));
  }

  // ---- the summary --------------------------------------------------------------
  report.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  report.primitive_calls = tactical.calls();
  report.sim_time_s = report.result ? report.result->sim_time_s : tactical.sim_time_s();
  report.phases = console.phases();
  // What the embedded vehicle did after we last heard from it.
  const double last_heard_s = tactical.sim_time_s();
  for (const auto& line : vehicle_log) {
    if (std::strtod(line.c_str(), nullptr) > last_heard_s + 1e-9) console.line("vehicle: " + line);
  }
  if (sim) {
    report.final_depth_m = sim->heave().depth_m;
    report.vehicle_watchdog_tripped = sim->watchdog_tripped();
    if (log) {
      log->write({{"event", "vehicle_final"},
                  {"depth_m", tactical::log_time(sim->heave().depth_m)},
                  {"watchdog_tripped", sim->watchdog_tripped()},
                  {"sim_time", tactical::log_time(sim->time_s())}});
    }
  }
  console.clear_status();

  if (!report.result) {
    err << "strata run: the mission did not start\n";
    return fail(kExitInternal);
  }
  const MissionResult& r = *report.result;
  const bool link_gone = link_lost || (r.call_error && (*r.call_error == core::ErrorCode::Timeout ||
                                                        *r.call_error == core::ErrorCode::Closed));
  std::string how = r.outcome == Outcome::Completed ? "completed"
                    : r.outcome == Outcome::Aborted ? "ABORTED"
                    : link_gone                     ? "ABORTED: lost the link to the vehicle"
                    : r.reason == kInterrupted      ? "ABORTED: interrupted by the operator"
                                                    : "ABORTED: the Strategic level could not go on";
  out << fmt::format("mission {}: {}{}\n", loaded.name, how,
                     r.exit.empty() ? "" : fmt::format(" (exit {})", r.exit));
  if (!r.reason.empty()) out << "  reason: " << r.reason << "\n";
  std::string phases;
  for (const auto& p : report.phases) phases += (phases.empty() ? "" : ", ") + p;
  out << "  phases: " << (phases.empty() ? "none ended" : phases) << "\n";
  double speedup = report.wall_time_s > 0 ? report.sim_time_s / report.wall_time_s : 0.0;
  out << fmt::format("  sim time {:.1f} s, {} primitive calls, wall time {}{}\n", report.sim_time_s,
                     report.primitive_calls, format_wall(report.wall_time_s),
                     lockstep && r.outcome != Outcome::Failed && speedup > 1.0
                         ? fmt::format(" ({:.0f}x real time)", speedup)
                         : "");
  if (report.final_depth_m) {
    out << fmt::format("  vehicle: depth {:.2f} m at {:.1f} s{}\n", *report.final_depth_m, sim->time_s(),
                       report.vehicle_watchdog_tripped ? ", surfaced by its own watchdog" : "");
  }
  if (link_lost) out << "  link: lost (" << link_lost_why << ")\n";
  if (sonar) out << "  sonar: " << sonar_summary(o.sonar_dir, report.sonar_exit) << "\n";
  if (report.emergency_surface) {
    out << fmt::format("  after it: exec surface sent by strata run; {}\n",
                       report.emergency_surfaced ? "the vehicle reached the surface" : "not confirmed at the surface");
  }
  if (report.emergency_shutdown) {
    out << fmt::format("  after it: ood shutdown_network sent by strata run{}\n",
                       emergency.shutdown_error().empty() ? "" : ", unanswered (" + emergency.shutdown_error() + ")");
  }
  if (log) {
    if (auto s = log->status(); !s) {
      err << "strata run: the mission log is incomplete: " << s.error().message << "\n";
      return fail(kExitIo);
    }
    out << "  log: " << log->path() << " (" << log->lines() << " lines)\n";
  }
  out.flush();
  report.exit_code = r.outcome == Outcome::Completed ? kExitOk : kExitAbort;
  return report;
}

}  // namespace strata::cli
