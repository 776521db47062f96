#include "cli/verbosity.h"

namespace strata::cli {

void add_verbosity_flags(CLI::App* cmd, VerbosityFlags& flags, const std::string& verbose_help) {
  auto* quiet = cmd->add_flag("-q,--quiet", flags.quiet, "Print only results and errors");
  auto* verbose = cmd->add_flag(
      "-v,--verbose", flags.verbose,
      verbose_help.empty() ? std::string("Accepted for every command; this one has no more to say") : verbose_help);
  quiet->excludes(verbose);
}

}  // namespace strata::cli
