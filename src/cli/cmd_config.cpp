// `strata config show` and `strata config path`: the operator's defaults
// (user_config.h) and where each comes from.
#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "cli/exit_codes.h"
#include "cli/user_config.h"

namespace strata::cli {

Runner add_config_command(CLI::App& app, const LoadedConfig& loaded) {
  auto* cmd = app.add_subcommand(
      "config", "Show the defaults strata takes from $XDG_CONFIG_HOME/strata/config.toml and the environment");
  cmd->require_subcommand(1);
  auto* show =
      cmd->add_subcommand("show", "Print every setting and where it comes from (file:line, environment, built in)");
  auto* path = cmd->add_subcommand("path", "Print the config file's path (it may not exist)");
  cmd->footer(
      "The file (TOML; every key optional):\n"
      "  [run]\n"
      "  vehicle = \"127.0.0.1:7020\"   # default --vehicle (\"embedded\": the simulated vehicle)\n"
      "  telemetry_hz = 5             # default --telemetry-hz\n"
      "  log = true                   # log every run to LOG_DIR/YYYYMMDDTHHMMSSZ-MISSION.jsonl\n"
      "  log_dir = \"~/auv/logs\"       # LOG_DIR (default $XDG_STATE_HOME/strata/logs)\n"
      "  [vehicle]\n"
      "  listen = \"127.0.0.1:7020\"    # strata vehicle --listen\n"
      "  [studio]\n"
      "  listen = \"127.0.0.1:0\"       # strata studio --listen\n"
      "STRATA_CONFIG names another file; STRATA_LOG_DIR beats log_dir; the command line beats both.\n"
      "Exit 0 when printed; 65 when the file is invalid (each problem at its line); 74 when it cannot be read.");
  return [&loaded, show, path] {
    if (path->parsed()) {
      std::cout << (loaded.config.path.empty() ? "(none: neither XDG_CONFIG_HOME nor HOME is set)" : loaded.config.path)
                << "\n";
      return static_cast<int>(kExitOk);
    }
    if (loaded.error) {
      std::cerr << "strata config: " << loaded.error->message << "\n";
      return exit_code_for_input(*loaded.error);
    }
    if (show->parsed()) std::cout << config_text(loaded.config);
    return static_cast<int>(kExitOk);
  };
}

}  // namespace strata::cli
