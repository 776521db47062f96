#pragma once
// What a mistyped command line gets besides CLI11's own message: the
// command or flag it probably meant, and the valid names.
//
//   strata verfy x.coral   -> strata: unknown command 'verfy': did you mean 'verify'?
//                             (and the list of commands)
//   strata run --scenaro x -> strata run: unknown option '--scenaro': did you mean '--scenario'?
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace strata::cli {

// Hints for argv against app's commands and options; empty when it has none
// (the command line's problem is something else: a missing value, a range).
std::vector<std::string> usage_hints(const CLI::App& app, int argc, const char* const* argv);

// The command argv names, as errors start: "strata run", "strata config
// show"; "strata" when argv names none.
std::string command_path(const CLI::App& app, int argc, const char* const* argv);

// What a command line that does not parse prints, every line of it:
// the hints when there are any, else "strata run: " and CLI11's message,
// then where the command's arguments are listed.
std::vector<std::string> usage_error(const CLI::App& app, const CLI::ParseError& error, int argc,
                                     const char* const* argv);

}  // namespace strata::cli
