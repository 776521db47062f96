#pragma once
// Each subcommand registers itself on the app and runs when chosen. A
// command's run function returns an ExitCode.
#include <cstdint>
#include <functional>
#include <string>
#include <utility>

#include <CLI/CLI.hpp>

#include "run/inputs.h"

namespace strata::cli {

using Runner = std::function<int()>;

// `strata check FILE...` and `strata dump FILE`.
Runner add_check_command(CLI::App& app);
Runner add_dump_command(CLI::App& app);
struct LoadedConfig;  // user_config.h: the operator's defaults, as main loaded them

// `strata vehicle`.
Runner add_vehicle_command(CLI::App& app, const LoadedConfig& config);
// `strata run`.
Runner add_run_command(CLI::App& app, const LoadedConfig& config);
// `strata compare`.
Runner add_compare_command(CLI::App& app);
// `strata verify`.
Runner add_verify_command(CLI::App& app);
// `strata studio`.
Runner add_studio_command(CLI::App& app, const LoadedConfig& config);
// `strata config show|path`.
Runner add_config_command(CLI::App& app, const LoadedConfig& config);
// `strata export`.
Runner add_export_command(CLI::App& app);
// `strata plot`.
Runner add_plot_command(CLI::App& app);
// `strata primitives`.
Runner add_primitives_command(CLI::App& app);
// `strata library`: the phase library's phases (docs/library.md).
Runner add_library_command(CLI::App& app);
// `strata sonar`.
Runner add_sonar_command(CLI::App& app);
// `strata completion SHELL` and the hidden `strata manpages DIR`: one
// runner for both (cli_docs.h). version: as --version prints it.
Runner add_docs_commands(CLI::App& app, const std::string& version);
// `strata campaign`.
Runner add_campaign_command(CLI::App& app);

// Shared with the run library (run/inputs.h).
using run::load_catalogue_option;
using run::load_scenario_option;
using run::parse_listen;

}  // namespace strata::cli
