#include <sstream>

#include <fmt/format.h>

#include "campaign/summary.h"
#include "core/diagnostic_printer.h"
#include "run/coral_load.h"
#include "run/inputs.h"

namespace strata::campaign {

core::Result<std::vector<std::string>> mission_transitions(const std::string& coral_path) {
  auto catalogue = run::load_catalogue_option("");
  if (!catalogue) return catalogue.error();
  run::CoralLoad load = run::load_coral_file(coral_path, catalogue.value());
  if (const auto failed = load.error()) {
    std::ostringstream text;
    core::print_diagnostics(text, load.sources, load.diagnostics);
    text << failed->message << "\n";
    return core::make_error(core::ErrorCode::InvalidInput, text.str());
  }
  std::vector<std::string> names;
  for (const coral::CompiledNet& net : load.program->nets) {
    for (petri::TransitionId t = 0; t < net.net.transition_count(); ++t) {
      names.push_back(fmt::format("{}.{}", net.name, net.net.transition_name(t)));
    }
  }
  return names;
}

}  // namespace strata::campaign
