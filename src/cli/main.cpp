// strata: strategic-level mission control for autonomous underwater vehicles.
#include <exception>
#include <iostream>
#include <map>

#include <CLI/CLI.hpp>

#include "cli/commands.h"
#include "cli/exit_codes.h"
#include "cli/usage_hints.h"
#include "cli/user_config.h"
#include "cli/verbosity.h"
#include "strata_version.h"

int main(int argc, char** argv) {
  using namespace strata;
  using namespace strata::cli;
  CLI::App app{"Strata: strategic-level mission control for AUVs (CORAL Petri nets and PROLOG rules)", "strata"};
  const std::string version = STRATA_VERSION " (" STRATA_REVISION ")";
  app.set_version_flag("--version", "strata " + version);
  app.require_subcommand(1);
  app.footer(exit_code_help());

  // The operator's defaults (config.toml, STRATA_LOG_DIR): read once; a
  // broken file stops only the commands that use it.
  LoadedConfig config;
  if (auto loaded = load_user_config()) {
    config.config = loaded.value();
  } else {
    config.error = loaded.error();
  }
  std::map<std::string, Runner> runners;
  runners["check"] = add_check_command(app);
  runners["dump"] = add_dump_command(app);
  runners["run"] = add_run_command(app, config);
  runners["compare"] = add_compare_command(app);
  runners["verify"] = add_verify_command(app);
  runners["export"] = add_export_command(app);
  runners["studio"] = add_studio_command(app, config);
  runners["vehicle"] = add_vehicle_command(app, config);
  runners["primitives"] = add_primitives_command(app);
  runners["library"] = add_library_command(app);
  runners["sonar"] = add_sonar_command(app);
  runners["plot"] = add_plot_command(app);
  runners["campaign"] = add_campaign_command(app);
  runners["config"] = add_config_command(app, config);
  runners["completion"] = runners["manpages"] = add_docs_commands(app, version);

  // Each command's --help ends with its own exit codes, not the program's;
  // each takes -q and -v (the commands with nothing to leave out or add
  // accept them all the same).
  // Their own subcommands (`config show`, `campaign merge`) take -q and -v too.
  VerbosityFlags unused;
  const auto all = [](CLI::App*) { return true; };
  for (CLI::App* sub : app.get_subcommands(all)) {
    if (sub->get_option_no_throw("--quiet") == nullptr) add_verbosity_flags(sub, unused, "");
    for (CLI::App* leaf : sub->get_subcommands(all)) {
      if (leaf->get_option_no_throw("--quiet") == nullptr) add_verbosity_flags(leaf, unused, "");
    }
    if (sub->get_footer().empty() || sub->get_footer() == app.get_footer()) {
      if (const char* codes = exit_codes_of(sub->get_name())) sub->footer(codes);
    }
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version end here too, with code 0, printed by CLI11.
    if (e.get_exit_code() == 0) return app.exit(e) == 0 ? kExitOk : kExitUsage;
    for (const auto& line : usage_error(app, e, argc, argv)) std::cerr << line << "\n";
    return kExitUsage;
  }
  try {
    for (auto* sub : app.get_subcommands()) return runners.at(sub->get_name())();
  } catch (const std::exception& e) {
    std::cerr << "strata: internal error: " << e.what() << "\n";
    return kExitInternal;
  }
  return kExitUsage;
}
