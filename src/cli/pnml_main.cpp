// strata-pnml: `strata verify --pnml` in a program of its own, linked with
// the nets alone (cli/pnml_verify.h): no PROLOG, missions, studio or
// vehicle code to load at each start.
#include <exception>
#include <iostream>

#include "cli/pnml_verify.h"
#include "cli/usage_hints.h"
#include "core/exit_codes.h"
#include "strata_version.h"

int main(int argc, char** argv) {
  using namespace strata::cli;
  PnmlCommandLine line(STRATA_VERSION " (" STRATA_REVISION ")");
  try {
    line.app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version end here too, with code 0, printed by CLI11.
    if (e.get_exit_code() == 0) return line.app.exit(e) == 0 ? strata::kExitOk : strata::kExitUsage;
    for (const auto& text : usage_error(line.app, e, argc, argv)) std::cerr << text << "\n";
    return strata::kExitUsage;
  }
  try {
    return run_pnml_command(line);
  } catch (const std::exception& e) {
    std::cerr << "strata-pnml: internal error: " << e.what() << "\n";
    return strata::kExitInternal;
  }
}
