// `strata run MISSION`: the mission against the simulated vehicle (or a real
// one), end to end.
#include <unistd.h>

#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "cli/exit_codes.h"
#include "cli/mission_run.h"
#include "cli/rule_load_flags.h"
#include "cli/studio_serve.h"

namespace strata::cli {

Runner add_run_command(CLI::App& app) {
  auto o = std::make_shared<RunOptions>();
  struct Studio {
    bool enabled = false;
    std::uint16_t port = 0;
  };
  auto studio = std::make_shared<Studio>();
  auto* cmd = app.add_subcommand(
      "run",
      "Run a mission: check and verify it, start the simulated vehicle on a free loopback port (unless "
      "--vehicle), and execute it through the Tactical level");
  cmd->add_option("mission", o->mission, "The mission: a CORAL net (.coral) or PROLOG rules (.pl)")->required();
  cmd->add_option("--data", o->data, "Mission data file (default: the one the mission names)");
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
  cmd->add_flag("--studio", studio->enabled,
                "Watch the run in the browser: serve the studio on the mission's folder (its address is the first "
                "line) and run on the wall clock at --speed");
  cmd->add_option("--studio-port", studio->port, "With --studio: the port (0: a free one)")->capture_default_str();
  cmd->add_flag("--realtime", o->realtime, "Run the embedded vehicle on the wall clock (default: lockstep)");
  cmd->add_option("--speed", o->speed,
                  "With --realtime: simulated seconds per wall second (with --vehicle: the speed "
                  "that vehicle runs at, to scale reply timeouts)")
      ->check(CLI::Range(0.01, 1000.0))
      ->capture_default_str();
  cmd->add_option("--vehicle", o->vehicle,
                  "HOST:PORT of a running vehicle (`strata vehicle`) instead of the embedded one");
  cmd->add_option("--log", o->log, "Write the mission log (JSON Lines) to this file");
  cmd->add_option("--answers", o->answers,
                  "Script the vehicle's answers from this file (`strata verify --witness-out` writes one): the run "
                  "follows that witness, and a mission that fails verification runs (docs/verification.md)");
  cmd->add_option("--sonar", o->sonar_dir,
                  "Start the Sonar Manager (`strata sonar`, a separate process) on the vehicle's sonar socket; "
                  "it writes the scans (PNG) and sonar.jsonl into this folder");
  cmd->add_option("--max-sim-time", o->max_sim_time_s,
                  "Lockstep: end the run (an abort: the vehicle is surfaced) after this many simulated seconds")
      ->check(CLI::Range(1.0, 1e9))
      ->capture_default_str();
  cmd->add_option("--telemetry-hz", o->telemetry_hz, "Telemetry asked of the vehicle, per simulated second")
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str();
  return [o, cmd, studio] {
    if (cmd->count("--speed") > 0 && !o->realtime && !studio->enabled && o->vehicle.empty()) {
      std::cerr << "strata run: --speed needs --realtime (lockstep runs as fast as it can)\n";
      return static_cast<int>(kExitUsage);
    }
    if (o->seed && o->mission.ends_with(".pl")) {
      std::cerr << "strata run: note: --seed chooses among enabled CORAL transitions; PROLOG rules "
                   "try their clauses in order, so it changes nothing here\n";
    }
    RunOptions options = *o;
    ConsoleOptions console;
    console.tty = isatty(STDOUT_FILENO) == 1;
    console.handle_signals = true;
    if (studio->enabled) {
      if (!o->mission.ends_with(".coral")) {
        std::cerr << "strata run: --studio shows CORAL missions (.coral)\n";
        return static_cast<int>(kExitUsage);
      }
      return serve_studio_run(options, "127.0.0.1", studio->port, std::cout, std::cerr).exit_code;
    }
    return run_mission(options, std::cout, std::cerr, console).exit_code;
  };
}

}  // namespace strata::cli
