// `strata run MISSION`: the mission against the simulated vehicle (or a real
// one), end to end.
#include <unistd.h>

#include <iostream>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "cli/validators.h"
#include "cli/commands.h"
#include "cli/exit_codes.h"
#include "cli/mission_run.h"
#include "cli/rule_load_flags.h"
#include "cli/run_flags.h"
#include "cli/studio_serve.h"
#include "cli/user_config.h"
#include "cli/verbosity.h"
#include "core/mission_language.h"

namespace strata::cli {
namespace {

// The options of `strata run` that are the command line's, not the run's.
struct RunCli {
  bool studio = false;
  std::string listen = "127.0.0.1:0";
  std::optional<std::uint16_t> studio_port;  // the old spelling of --listen PORT
  std::optional<double> studio_wait_s;
  std::string format = "text";
  VerbosityFlags verbosity;
  bool no_log = false;
};

int usage(const std::string& text) {
  std::cerr << "strata run: " << text << "\n";
  return kExitUsage;
}

int run_command(const RunOptions& o, const CLI::App& cmd, const RunCli& c, const LoadedConfig& config) {
  if (auto failed = config_failure(config, "run")) return *failed;
  const bool embedded = o.vehicle.empty() || o.vehicle == "embedded";
  if (cmd.count("--speed") > 0 && !o.realtime && !c.studio && embedded) {
    return usage("--speed needs --realtime (lockstep runs as fast as it can)");
  }
  const bool listen_given = cmd.count("--listen") > 0 || c.studio_port;
  if (!c.studio && (listen_given || c.studio_wait_s)) return usage("--listen and --studio-wait need --studio");
  if (cmd.count("--listen") > 0 && c.studio_port) return usage("give --listen alone (--studio-port is its old name)");
  if (c.studio && c.format == "json")
    return usage("--format json prints one document; --studio prints the page's address");
  if (o.seed && core::mission_language(o.mission) == core::MissionLanguage::Prolog) {
    std::cerr << "strata run: note: --seed chooses among enabled CORAL transitions; PROLOG rules "
                 "try their clauses in order, so it changes nothing here\n";
  }
  if (c.no_log && !o.log.empty()) return usage("--log FILE and --no-log: give one");
  RunOptions options = o;
  if (options.vehicle == "embedded") options.vehicle.clear();
  options.reuse_rules = false;  // one run: no later one of this process takes the rules back
  if (c.studio && core::mission_language(o.mission) != core::MissionLanguage::Coral)
    return usage("--studio shows CORAL missions (.coral)");
  // Every run is logged unless the operator says not (--no-log, or log =
  // false in the config): to a dated file under the log folder.
  const UserConfig& settings = config.config;
  // The run creates it (tactical::MissionLog::open_dated), once its inputs load.
  if (options.log.empty() && !c.no_log && settings.run_log.value) {
    if (settings.run_log_dir.value.empty()) {
      std::cerr << "strata run: note: not logging this run: no log folder (set STRATA_LOG_DIR, or --log FILE)\n";
    } else {
      options.log_dir = settings.run_log_dir.value;
    }
  }
  if (c.studio) {
    std::string listen = c.listen;
    if (c.studio_port) {
      std::cerr << "strata run: note: --studio-port is now --listen ADDRESS:PORT; the old name goes in a later "
                   "release\n";
      listen = std::to_string(*c.studio_port);
    }
    auto endpoint = parse_listen(listen);
    if (!endpoint) return usage("--listen: " + endpoint.error().message);
    StudioRunWait wait;
    wait.seconds = c.studio_wait_s;
    wait.terminal = isatty(STDIN_FILENO) == 1 && isatty(STDOUT_FILENO) == 1;
    const RunReport report =
        serve_studio_run(options, endpoint.value().first, endpoint.value().second, wait, std::cout, std::cerr);
    return report.exit_code;
  }
  ConsoleOptions console;
  console.tty = isatty(STDOUT_FILENO) == 1;
  console.handle_signals = true;
  console.verbosity = c.verbosity.level();
  console.json = c.format == "json";
  const RunReport report = run_mission(options, std::cout, std::cerr, console);
  return report.exit_code;
}

}  // namespace

Runner add_run_command(CLI::App& app, const LoadedConfig& config) {
  auto o = std::make_shared<RunOptions>();
  // The operator's defaults (user_config.h); the command line beats them.
  o->vehicle = config.config.run_vehicle.value;
  o->telemetry_hz = config.config.run_telemetry_hz.value;
  auto c = std::make_shared<RunCli>();
  auto* cmd =
      app.add_subcommand("run",
                         "Run a mission: check and verify it, start the simulated vehicle in this process (unless "
                         "--vehicle), and execute it through the Tactical level");
  cmd->add_option("mission", o->mission, "The mission: a CORAL net (.coral) or PROLOG rules (.pl)")->required();
  add_shared_run_flags(cmd, *o);
  cmd->add_option("--scenario", o->scenario,
                  "Vehicle scenario: NAME in the mission's scenarios/ folder, or a path (default: the mission's "
                  "scenarios/nominal.toml if it has one, else no faults)");
  cmd->add_option("--params", o->params, "Vehicle parameter file (default: built in, as config/phoenix.toml)");
  cmd->add_option("--catalogue", o->catalogue, "Primitive catalogue (default: built in)");
  cmd->add_option("--seed", o->seed,
                  "Choose among enabled transitions of equal priority at random, from this seed "
                  "(default: declaration order)");
  cmd->add_option("--inference-limit", o->inference_limit,
                  "PROLOG: inferences the rules may make between two primitive calls before the "
                  "mission is stopped as an endless loop")
      ->check(CLI::Range(std::uint64_t{1000}, std::uint64_t{1'000'000'000'000}))
      ->capture_default_str();
  add_rule_load_flags(cmd, o->rule_load);
  cmd->add_flag("--unverified", o->unverified,
                "CORAL: run the mission even if `strata verify` finds a property that fails (the failures "
                "are printed and the mission log records them)");
  cmd->add_flag("--studio", c->studio,
                "Watch the run in the browser: serve the studio on the mission's folder (its address is the first "
                "line) and run on the wall clock at --speed");
  cmd->add_option("--listen", c->listen, "With --studio: ADDRESS:PORT or PORT the studio listens on (0: a free port)")
      ->capture_default_str();
  cmd->add_option("--studio-port", c->studio_port, "Old spelling of --listen PORT")->group("");
  cmd->add_option("--studio-wait", c->studio_wait_s,
                  "With --studio: keep serving this many seconds after the run (Ctrl-C ends it sooner; default: "
                  "until Ctrl-C on a terminal, not at all otherwise)")
      ->check(finite_range(0.0, 86400.0 * 365));
  cmd->add_flag("--realtime", o->realtime, "Run the embedded vehicle on the wall clock (default: lockstep)");
  cmd->add_option("--speed", o->speed,
                  "With --realtime: simulated seconds per wall second (with --vehicle: the speed "
                  "that vehicle runs at, to scale reply timeouts)")
      ->check(finite_range(0.01, 1000.0))
      ->capture_default_str();
  cmd->add_option("--vehicle", o->vehicle,
                  "ADDRESS:PORT or PORT of a running vehicle (`strata vehicle`); imc://HOST:PORT[/ID] of an IMC "
                  "vehicle (LSTS DUNE, `strata vehicle --imc`; docs/imc.md); or embedded: the simulated one "
                  "started for this run")
      ->capture_default_str();
  cmd->add_option("--log", o->log,
                  "Write the mission log (JSON Lines) to this file (default: a dated file in the log folder, "
                  "`strata config show` says where)");
  cmd->add_flag("--no-log", c->no_log, "Write no mission log");
  cmd->add_option("--answers", o->answers,
                  "Script the vehicle's answers from this file (`strata verify --witness-out` writes one): the run "
                  "follows that witness, and a mission that fails verification runs (docs/verification.md)");
  cmd->add_option("--sonar", o->sonar_dir,
                  "Start the Sonar Manager (`strata sonar`, a separate process) on the vehicle's sonar socket; "
                  "it writes the scans (PNG) and sonar.jsonl into this folder");
  cmd->add_option_function<std::uint64_t>(
         "--max-log-mb", [o](std::uint64_t mb) { o->max_log_bytes = mb << 20; },
         "End the run (an abort: the vehicle is surfaced) when its mission log reaches this many MB, and write "
         "no more of it; 0: no bound")
      ->check(CLI::Range(std::uint64_t{0}, std::uint64_t{1} << 20))
      ->default_str(std::to_string(run::RunOptions{}.max_log_bytes >> 20));
  cmd->add_option("--format", c->format, "text, or json: the summary as one JSON document on stdout, no event lines")
      ->check(CLI::IsMember({"text", "json"}))
      ->capture_default_str();
  add_verbosity_flags(cmd, c->verbosity, "Also a line for each primitive call, with its arguments, and its answer");
  return [o, cmd, c, &config] { return run_command(*o, *cmd, *c, config); };
}

}  // namespace strata::cli
