#include "studio/run_list.h"

#include <algorithm>
#include <filesystem>

#include <fmt/format.h>

namespace strata::studio {

namespace fs = std::filesystem;
using nlohmann::json;

json run_list(const Sandbox& sandbox, const std::string& mission) {
  std::string folder, stem;
  if (!mission.empty()) {
    const fs::path m(mission);
    folder = m.parent_path().generic_string();
    folder = folder.empty() ? "runs" : folder + "/runs";
    stem = m.filename().string();
  }
  json runs = json::array();
  for (const auto& log : sandbox.list({".jsonl"})) {
    const fs::path p(log);
    if (p.parent_path().filename() != "runs") continue;
    if (!mission.empty() && p.parent_path().generic_string() != folder) continue;
    // NAME: 20261125T214638Z-tank.coral[-N] (before 26 November 2026:
    // -tank[-N], the stem only, which any mission of that stem matches)
    const std::string name = p.stem().string();
    if (name.size() < 18 || name[8] != 'T' || name[15] != 'Z' || name[16] != '-') continue;
    std::string of = name.substr(17);
    if (auto dash = of.rfind('-'); dash != std::string::npos &&
                                   of.find_first_not_of("0123456789", dash + 1) == std::string::npos &&
                                   dash + 1 < of.size()) {
      of = of.substr(0, dash);
    }
    if (!mission.empty() && of != stem &&
        !(of.find('.') == std::string::npos && of == fs::path(stem).stem().string())) {
      continue;
    }
    std::error_code ec;
    const auto bytes = fs::file_size(sandbox.root() / log, ec);
    const std::string stamp = name.substr(0, 16);
    runs.push_back(
        {{"path", log},
         {"mission_file", of},
         {"started", fmt::format("{}-{}-{}T{}:{}:{}Z", stamp.substr(0, 4), stamp.substr(4, 2), stamp.substr(6, 2),
                                 stamp.substr(9, 2), stamp.substr(11, 2), stamp.substr(13, 2))},
         {"bytes", ec ? 0 : bytes}});
  }
  std::sort(runs.begin(), runs.end(), [](const json& a, const json& b) {
    return a["started"] != b["started"] ? a["started"] > b["started"] : a["path"] > b["path"];
  });
  return {{"runs", runs}};
}

}  // namespace strata::studio
