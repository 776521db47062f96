// `strata vehicle`: the simulated Phoenix (Execution level) on a TCP port,
// or (--imc) as an IMC vehicle on a UDP port.
#include <charconv>
#include <filesystem>
#include <iostream>
#include <memory>

#include <asio.hpp>
#include <fmt/format.h>

#include "cli/validators.h"
#include "cli/commands.h"
#include "cli/exit_codes.h"
#include "cli/user_config.h"
#include "cli/verbosity.h"
#include "vehicle/execution.h"
#include "vehicle/imc_server.h"
#include "vehicle/params.h"
#include "vehicle/scenario.h"
#include "vehicle/server.h"

namespace strata::cli {
namespace {

struct VehicleOptions {
  std::string listen = "127.0.0.1:7020";
  std::string params;
  std::string scenario;
  std::string mission;
  std::optional<std::uint64_t> seed;
  bool realtime = false;
  double speed = 1.0;
  double hello_timeout_s = vehicle::ServerOptions{}.hello_timeout_s;
  bool interface = false;
  bool trace = false;  // the old spelling of -v
  VerbosityFlags verbosity;
  // --imc: IMC over UDP (docs/imc.md)
  bool imc = false;
  bool imc_lockstep = false;  // --lockstep
  std::optional<std::uint16_t> port;
  std::string imc_id = "0x2C01";
  bool imc_id_given = false;
  bool listen_given = false;
  bool hello_timeout_given = false;
};

// "0x2C01" or "11265": an IMC system id a vehicle may take: 1 to 0xFFEF
// (0xFFF0 is "any vehicle", 0xFFFF the broadcast).
std::optional<std::uint16_t> parse_imc_id(const std::string& text) {
  const bool hex = text.starts_with("0x") || text.starts_with("0X");
  const char* first = text.data() + (hex ? 2 : 0);
  const char* last = text.data() + text.size();
  std::uint16_t id = 0;
  auto [end, ec] = std::from_chars(first, last, id, hex ? 16 : 10);
  if (ec != std::errc{} || end != last || first == last) return std::nullopt;
  if (id == 0 || id > 0xFFEF) return std::nullopt;
  return id;
}

// Why the options cannot go together, or "" when they can.
std::string imc_conflict(const VehicleOptions& o) {
  if (!o.imc) {
    if (o.port) return "--port is for --imc (the Phoenix protocol listens on --listen ADDRESS:PORT)";
    if (o.imc_lockstep) return "--lockstep is for --imc (the Phoenix protocol is in lockstep unless --realtime)";
    if (o.imc_id_given) return "--imc-id is for --imc";
    return "";
  }
  if (o.interface) return "--interface prints the Phoenix protocol; --imc speaks IMC (docs/imc.md)";
  if (o.hello_timeout_given) return "--hello-timeout is the Phoenix protocol's; an IMC peer announces itself";
  if (o.listen_given && o.port) return "give --port or --listen, not both";
  if (o.imc_lockstep && o.realtime) return "give --lockstep or --realtime, not both";
  return "";
}

// "leak (a leak at 20 s)": the scenario as named, and its description when
// it says more.
std::string scenario_label(const VehicleOptions& o, const vehicle::Scenario& scenario) {
  std::string name = o.scenario.empty() ? "nominal" : o.scenario;
  if (scenario.description.empty() || scenario.description == name) return name;
  return fmt::format("{} ({})", name, scenario.description);
}

int run_imc_vehicle(const VehicleOptions& o, const vehicle::VehicleParams& params, const vehicle::Scenario& scenario) {
  vehicle::ImcServerOptions so;
  so.port = o.port.value_or(6002);
  if (o.listen_given) {
    auto endpoint = parse_listen(o.listen);
    if (!endpoint) {
      std::cerr << "strata vehicle: " << endpoint.error().message << "\n";
      return kExitUsage;
    }
    so.address = endpoint.value().first;
    so.port = endpoint.value().second;
  }
  so.speed = o.speed;
  so.lockstep = o.imc_lockstep;
  so.imc_id = *parse_imc_id(o.imc_id);
  so.trace = o.trace || o.verbosity.level() == Verbosity::Verbose;
  so.log = [](const std::string& line) { std::cerr << "vehicle: " << line << std::endl; };
  asio::io_context io;
  vehicle::Simulation sim(params, scenario);
  vehicle::ImcVehicleServer server(io, sim, so);
  if (auto r = server.start(); !r) {
    std::cerr << "strata vehicle: " << r.error().message << "\n";
    return kExitIo;
  }
  // The first line of stdout says where, for scripts and tests.
  std::cout << fmt::format("imc vehicle {} (id 0x{:04X}) on udp://{}:{}", so.system_name, so.imc_id, so.address,
                           server.port())
            << std::endl;
  const bool quiet = o.verbosity.level() == Verbosity::Quiet;
  if (!quiet) {
    std::cerr << fmt::format(
                     "vehicle: IMC on udp://{}:{} ({}, scenario {}, seed {}); "
                     "announce to it to be heard",
                     so.address, server.port(),
                     so.lockstep ? "lockstep with its controller" : fmt::format("wall clock, speed {}", o.speed),
                     scenario_label(o, scenario), scenario.seed)
              << std::endl;
  }
  asio::signal_set signals(io, SIGINT, SIGTERM);
  signals.async_wait([&](const asio::error_code& e, int) {
    if (e) return;
    if (!quiet) {
      std::cerr << fmt::format("vehicle: stopping; {} datagrams read, {} dropped ({}){}", server.counts().datagrams,
                               server.counts().dropped.total(), server.counts().dropped.summary(),
                               so.lockstep ? fmt::format("; {} cycles unanswered (lockstep)",
                                                         server.counts().lockstep_waits_ended)
                                           : "")
                << std::endl;
    }
    server.stop();
    io.stop();
  });
  io.run();
  return kExitOk;
}

int run_vehicle(const VehicleOptions& o) {
  if (o.trace) std::cerr << "strata vehicle: note: --trace is now -v/--verbose; the old name goes in a later release\n";
  if (auto why = imc_conflict(o); !why.empty()) {
    std::cerr << "strata vehicle: " << why << "\n";
    return kExitUsage;
  }
  if (o.imc && !parse_imc_id(o.imc_id)) {
    std::cerr << "strata vehicle: --imc-id " << o.imc_id
              << ": not an IMC system id a vehicle can take (1 to 0xFFEF, e.g. 0x2C01)\n";
    return kExitUsage;
  }
  if (o.interface) {
    std::cout << vehicle::interface_text();
    return kExitOk;
  }
  auto endpoint = parse_listen(o.imc && !o.listen_given ? std::string("127.0.0.1:0") : o.listen);
  if (!endpoint) {
    std::cerr << "strata vehicle: " << endpoint.error().message << "\n";
    return kExitUsage;
  }
  vehicle::VehicleParams params = vehicle::default_params();
  if (!o.params.empty()) {
    auto p = vehicle::load_params(o.params);
    if (!p) {
      std::cerr << "strata vehicle: " << p.error().message << "\n";
      return exit_code_for_input(p.error());
    }
    params = p.value();
  }
  auto scenario = load_scenario_option(o.scenario, o.mission);
  if (!scenario) {
    std::cerr << "strata vehicle: " << scenario.error().message << "\n";
    return exit_code_for_input(scenario.error());
  }
  if (o.seed) scenario.value().seed = *o.seed;
  if (o.imc) return run_imc_vehicle(o, params, scenario.value());

  asio::io_context io;
  vehicle::Simulation sim(params, scenario.value());
  vehicle::ServerOptions so;
  so.address = endpoint.value().first;
  so.port = endpoint.value().second;
  so.clock = o.realtime ? protocol::ClockMode::Wall : protocol::ClockMode::Lockstep;
  so.speed = o.speed;
  so.hello_timeout_s = o.hello_timeout_s;
  so.trace = o.trace || o.verbosity.level() == Verbosity::Verbose;
  so.log = [](const std::string& line) { std::cerr << "vehicle: " << line << std::endl; };
  const bool quiet = o.verbosity.level() == Verbosity::Quiet;
  vehicle::VehicleServer server(io, sim, so);
  if (auto r = server.start(); !r) {
    std::cerr << "strata vehicle: " << r.error().message << "\n";
    return kExitIo;
  }
  // The first line of stdout is the address, for scripts and tests.
  std::cout << so.address << ":" << server.port() << std::endl;
  if (!quiet) {
    std::cerr << fmt::format("vehicle: listening on {}:{} ({} clock{}, scenario {}, seed {})", so.address,
                             server.port(), o.realtime ? "wall" : "lockstep",
                             o.realtime ? fmt::format(", speed {}", o.speed) : "", scenario_label(o, scenario.value()),
                             scenario.value().seed)
              << std::endl;
    std::cerr << fmt::format("vehicle: sonar socket on {}:{} (`strata sonar --stream {}:{} --out DIR` reads it)",
                             so.address, server.sonar_port(), so.address, server.sonar_port())
              << std::endl;
  }
  asio::signal_set signals(io, SIGINT, SIGTERM);
  signals.async_wait([&](const asio::error_code& e, int) {
    if (e) return;
    if (!quiet) std::cerr << "vehicle: stopping" << std::endl;
    server.stop();
    io.stop();
  });
  io.run();
  return kExitOk;
}

}  // namespace

Runner add_vehicle_command(CLI::App& app, const LoadedConfig& config) {
  auto o = std::make_shared<VehicleOptions>();
  o->listen = config.config.vehicle_listen.value;
  auto* cmd = app.add_subcommand(
      "vehicle", "Run the simulated Phoenix (Execution level) on a TCP port, or as an IMC vehicle on UDP (--imc)");
  cmd->add_option("--listen", o->listen,
                  "PORT or ADDRESS:PORT to listen on; 0 picks a free port (printed on the first line)")
      ->capture_default_str();
  cmd->add_option("--params", o->params, "Vehicle parameter file (default: built in, as config/phoenix.toml)");
  cmd->add_option("--scenario", o->scenario, "Scenario: a path, or NAME in the --mission's scenarios/ folder");
  cmd->add_option("--mission", o->mission, "Mission file whose scenarios/ folder --scenario NAME is looked up in");
  cmd->add_option("--seed", o->seed, "Seed for noise and faults (overrides the scenario's)");
  cmd->add_flag("--realtime", o->realtime, "Run on the wall clock (default: lockstep virtual time)");
  cmd->add_option("--speed", o->speed, "With --realtime or --imc: simulated seconds per wall second")
      ->check(finite_range(0.01, 1000.0))
      ->capture_default_str();
  cmd->add_option("--hello-timeout", o->hello_timeout_s,
                  "Wall seconds a client has to say hello after connecting; then it is sent an error and "
                  "dropped, so that it cannot hold the vehicle (0: wait for ever)")
      ->check(finite_range(0.0, 86400.0))
      ->capture_default_str();
  cmd->add_flag("--imc", o->imc,
                "Speak IMC (LSTS, 5.4) over UDP instead of the Phoenix protocol: an IMC vehicle steered by a "
                "FollowReference plan, on the wall clock unless --lockstep (docs/imc.md)");
  cmd->add_flag("--lockstep", o->imc_lockstep,
                "With --imc: step each cycle when the controller (a Strata run) has done with the last one, not "
                "on the wall clock: as fast as it goes, the same run whatever the machine's load");
  cmd->add_option("--port", o->port,
                  "With --imc: the UDP port on 127.0.0.1 (default 6002, DUNE's; 0 picks a free port, printed on "
                  "the first line)");
  cmd->add_option("--imc-id", o->imc_id, "With --imc: this vehicle's IMC system id, hex (0x...) or decimal")
      ->capture_default_str();
  cmd->add_flag("--interface", o->interface, "Print every message the vehicle accepts and emits, and exit");
  cmd->add_flag("--trace", o->trace, "Old spelling of --verbose")->group("");
  add_verbosity_flags(cmd, o->verbosity, "Log every line received and sent (stderr)");
  return [o, cmd, &config] {
    if (auto failed = config_failure(config, "vehicle")) return *failed;
    o->listen_given = cmd->count("--listen") > 0;
    o->hello_timeout_given = cmd->count("--hello-timeout") > 0;
    o->imc_id_given = cmd->count("--imc-id") > 0;
    return run_vehicle(*o);
  };
}

}  // namespace strata::cli
