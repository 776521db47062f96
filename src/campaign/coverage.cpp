#include <sstream>

#include <fmt/format.h>

#include "campaign/summary.h"
#include "run/coral_load.h"
#include "run/inputs.h"

namespace strata::campaign {

core::Result<std::vector<std::string>> mission_transitions(const std::string& coral_path) {
  auto catalogue = run::load_catalogue_option("");
  if (!catalogue) return catalogue.error();
  std::ostringstream err;
  run::CoralLoad load = run::load_coral_file(coral_path, catalogue.value(), err, "strata campaign");
  if (!load.program) return core::make_error(core::ErrorCode::InvalidInput, err.str());
  std::vector<std::string> names;
  for (const coral::CompiledNet& net : load.program->nets) {
    for (petri::TransitionId t = 0; t < net.net.transition_count(); ++t) {
      names.push_back(fmt::format("{}.{}", net.name, net.net.transition_name(t)));
    }
  }
  return names;
}

}  // namespace strata::campaign
