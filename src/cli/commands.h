#pragma once
// Each subcommand registers itself on the app and runs when chosen. A
// command's run function returns an ExitCode.
#include <functional>

#include <CLI/CLI.hpp>

namespace strata::cli {

using Runner = std::function<int()>;

// `strata check FILE...` and `strata dump FILE`.
Runner add_check_command(CLI::App& app);
Runner add_dump_command(CLI::App& app);

}  // namespace strata::cli
