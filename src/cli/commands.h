#pragma once
// Each subcommand registers itself on the app and runs when chosen. A
// command's run function returns an ExitCode.
#include <cstdint>
#include <functional>
#include <string>
#include <utility>

#include <CLI/CLI.hpp>

#include "core/result.h"
#include "tactical/catalogue.h"
#include "vehicle/scenario.h"

namespace strata::cli {

using Runner = std::function<int()>;

// `strata check FILE...` and `strata dump FILE`.
Runner add_check_command(CLI::App& app);
Runner add_dump_command(CLI::App& app);
// `strata vehicle`.
Runner add_vehicle_command(CLI::App& app);
// `strata run`.
Runner add_run_command(CLI::App& app);
// `strata compare`.
Runner add_compare_command(CLI::App& app);
// `strata verify`.
Runner add_verify_command(CLI::App& app);
// `strata studio`.
Runner add_studio_command(CLI::App& app);
// `strata export`.
Runner add_export_command(CLI::App& app);
// `strata plot`.
Runner add_plot_command(CLI::App& app);
// `strata primitives`.
Runner add_primitives_command(CLI::App& app);
// `strata sonar`.
Runner add_sonar_command(CLI::App& app);

// "PORT" or "ADDRESS:PORT" (ADDRESS defaults to 127.0.0.1).
core::Result<std::pair<std::string, std::uint16_t>> parse_listen(const std::string& text);
// --catalogue: the built-in catalogue when empty, else the file.
core::Result<tactical::Catalogue> load_catalogue_option(const std::string& path);
// --scenario: nominal when empty; a path; or NAME in the mission's scenarios/.
core::Result<vehicle::Scenario> load_scenario_option(const std::string& scenario,
                                                     const std::string& mission);

}  // namespace strata::cli
