// `strata primitives`: the Tactical level's primitive catalogue.
#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "cli/exit_codes.h"
#include "core/diagnostic_printer.h"
#include "tactical/catalogue.h"
#include "tactical/catalogue_print.h"

namespace strata::cli {
namespace {

struct PrimitivesOptions {
  std::string catalogue;
  std::string format = "text";
};

int run_primitives(const PrimitivesOptions& o) {
  auto loaded = load_catalogue_option(o.catalogue);
  if (!loaded) {
    std::cerr << "strata primitives: " << loaded.error().message << "\n";
    return exit_code_for_input(loaded.error());
  }
  if (o.format == "json") {
    std::cout << tactical::catalogue_json(loaded.value()).dump(2) << "\n";
  } else {
    std::cout << tactical::format_catalogue(loaded.value());
  }
  return kExitOk;
}

}  // namespace

Runner add_primitives_command(CLI::App& app) {
  auto o = std::make_shared<PrimitivesOptions>();
  auto* cmd = app.add_subcommand("primitives", "Print the vehicle primitives a mission may call");
  cmd->add_option("--catalogue", o->catalogue, "Catalogue file (default: built in, as config/primitives.toml)");
  cmd->add_option("--format", o->format, "text or json")->check(CLI::IsMember({"text", "json"}))->capture_default_str();
  return [o] { return run_primitives(*o); };
}

}  // namespace strata::cli
