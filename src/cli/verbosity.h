#pragma once
// -q/--quiet and -v/--verbose: every command takes both, with the same
// meaning: quiet prints only results and errors, verbose adds the detail
// behind them. Each command says in its help what the detail is.
#include <string>

#include <CLI/CLI.hpp>

namespace strata::cli {

enum class Verbosity { Quiet, Normal, Verbose };

struct VerbosityFlags {
  bool quiet = false;
  bool verbose = false;
  Verbosity level() const { return quiet ? Verbosity::Quiet : verbose ? Verbosity::Verbose : Verbosity::Normal; }
};

// Adds -q,--quiet and -v,--verbose (excluding each other) to cmd.
// verbose_help: what -v adds on this command ("" when it has nothing to add).
void add_verbosity_flags(CLI::App* cmd, VerbosityFlags& flags, const std::string& verbose_help);

}  // namespace strata::cli
