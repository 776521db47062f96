// strata: strategic-level mission control for autonomous underwater vehicles.
#include <exception>
#include <iostream>
#include <map>
#include <optional>
#include <string_view>

#include <CLI/CLI.hpp>

#include "cli/commands.h"
#include "cli/exit_codes.h"
#include "cli/usage_hints.h"
#include "cli/user_config.h"
#include "cli/verbosity.h"
#include "strata_version.h"

namespace {

using namespace strata;
using namespace strata::cli;

using Runners = std::map<std::string, Runner, std::less<>>;
using AddCommand = Runner (*)(CLI::App&, const LoadedConfig&);

// The commands, in the order --help lists them (the docs commands, which
// describe the whole app, come last: add_commands).
constexpr std::pair<std::string_view, AddCommand> kCommands[] = {
    {"check", [](CLI::App& app, const LoadedConfig&) { return add_check_command(app); }},
    {"dump", [](CLI::App& app, const LoadedConfig&) { return add_dump_command(app); }},
    {"run", [](CLI::App& app, const LoadedConfig& config) { return add_run_command(app, config); }},
    {"compare", [](CLI::App& app, const LoadedConfig&) { return add_compare_command(app); }},
    {"verify", [](CLI::App& app, const LoadedConfig&) { return add_verify_command(app); }},
    {"export", [](CLI::App& app, const LoadedConfig&) { return add_export_command(app); }},
    {"studio", [](CLI::App& app, const LoadedConfig& config) { return add_studio_command(app, config); }},
    {"vehicle", [](CLI::App& app, const LoadedConfig& config) { return add_vehicle_command(app, config); }},
    {"primitives", [](CLI::App& app, const LoadedConfig&) { return add_primitives_command(app); }},
    {"library", [](CLI::App& app, const LoadedConfig&) { return add_library_command(app); }},
    {"sonar", [](CLI::App& app, const LoadedConfig&) { return add_sonar_command(app); }},
    {"plot", [](CLI::App& app, const LoadedConfig&) { return add_plot_command(app); }},
    {"campaign", [](CLI::App& app, const LoadedConfig&) { return add_campaign_command(app); }},
    {"config", [](CLI::App& app, const LoadedConfig& config) { return add_config_command(app, config); }},
};

// The command argv[1] names, when it can be parsed with no other command
// registered: setting up every command's options is about a third of a
// millisecond of each start (docs/prolog.md, start-up). Empty otherwise
// (no command first, `completion` and `manpages`, which describe the whole
// app, or another command's name further on, which CLI11 could look up
// among the siblings).
std::string_view command_asked(int argc, const char* const* argv) {
  if (argc < 2) return {};
  const std::string_view first = argv[1];
  const auto is_command = [](std::string_view arg) {
    for (const auto& [name, add] : kCommands) {
      if (name == arg) return true;
    }
    return arg == "completion" || arg == "manpages";
  };
  if (first == "completion" || first == "manpages" || !is_command(first)) return {};
  for (int i = 2; i < argc; ++i) {
    if (is_command(argv[i])) return {};
  }
  return first;
}

constexpr const char* kDescription =
    "Strata: strategic-level mission control for AUVs (CORAL Petri nets and PROLOG rules)";

// The command line: the app, what runs each command, and where the -q and
// -v of the commands that ignore them go (the app binds to it: it lives as
// long as the app).
struct CommandLine {
  CLI::App app{kDescription, "strata"};
  Runners runners;
  VerbosityFlags unused;
};

// The app with every command (only empty) or with one.
void add_commands(CommandLine& line, const LoadedConfig& config, const std::string& version, std::string_view only) {
  CLI::App& app = line.app;
  Runners& runners = line.runners;
  app.set_version_flag("--version", "strata " + version);
  app.require_subcommand(1);
  app.footer(exit_code_help());
  for (const auto& [name, add] : kCommands) {
    if (only.empty() || only == name) runners.emplace(name, add(app, config));
  }
  if (only.empty()) runners["completion"] = runners["manpages"] = add_docs_commands(app, version);

  // Each command's --help ends with its own exit codes, not the program's;
  // each takes -q and -v (the commands with nothing to leave out or add
  // accept them all the same).
  // Their own subcommands (`config show`, `campaign merge`) take -q and -v too.
  const auto all = [](CLI::App*) { return true; };
  for (CLI::App* sub : app.get_subcommands(all)) {
    if (sub->get_option_no_throw("--quiet") == nullptr) add_verbosity_flags(sub, line.unused, "");
    for (CLI::App* leaf : sub->get_subcommands(all)) {
      if (leaf->get_option_no_throw("--quiet") == nullptr) add_verbosity_flags(leaf, line.unused, "");
    }
    if (sub->get_footer().empty() || sub->get_footer() == app.get_footer()) {
      if (const char* codes = exit_codes_of(sub->get_name())) sub->footer(codes);
    }
  }
}

// Parses argv and runs the command it names. A parse error (a usage error,
// --help, --version) is answered here when answer_errors, and is nullopt
// otherwise.
std::optional<int> parse_and_run(CommandLine& command_line, int argc, char** argv, bool answer_errors) {
  CLI::App& app = command_line.app;
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (!answer_errors) return std::nullopt;
    // --help and --version end here too, with code 0, printed by CLI11.
    if (e.get_exit_code() == 0) return app.exit(e) == 0 ? kExitOk : kExitUsage;
    for (const auto& line : usage_error(app, e, argc, argv)) std::cerr << line << "\n";
    return kExitUsage;
  }
  try {
    for (auto* sub : app.get_subcommands()) return command_line.runners.at(sub->get_name())();
  } catch (const std::exception& e) {
    std::cerr << "strata: internal error: " << e.what() << "\n";
    return kExitInternal;
  }
  return kExitUsage;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string version = STRATA_VERSION " (" STRATA_REVISION ")";

  // The operator's defaults (config.toml, STRATA_LOG_DIR): read once; a
  // broken file stops only the commands that use it.
  LoadedConfig config;
  if (auto loaded = load_user_config()) {
    config.config = loaded.value();
  } else {
    config.error = loaded.error();
  }

  // The command asked for alone; whatever it cannot parse is parsed again
  // by the whole app, so that errors and help read as they always have.
  if (const std::string_view asked = command_asked(argc, argv); !asked.empty()) {
    CommandLine one;
    add_commands(one, config, version, asked);
    if (auto code = parse_and_run(one, argc, argv, /*answer_errors=*/false)) return *code;
  }
  CommandLine whole;
  add_commands(whole, config, version, {});
  return *parse_and_run(whole, argc, argv, /*answer_errors=*/true);
}
