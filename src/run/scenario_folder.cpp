#include "run/scenario_folder.h"

#include <algorithm>

namespace strata::run {

namespace fs = std::filesystem;

fs::path scenarios_folder(const std::string& mission) { return fs::path(mission).parent_path() / "scenarios"; }

fs::path scenario_path(const std::string& mission, const std::string& name) {
  return scenarios_folder(mission) / (name + ".toml");
}

std::vector<std::string> scenario_names_in(const fs::path& folder) {
  std::vector<std::string> names;
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    if (it->path().extension() == ".toml" && it->is_regular_file(ec)) names.push_back(it->path().stem().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace strata::run
