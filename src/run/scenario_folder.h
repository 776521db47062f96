#pragma once
// Where a mission's named scenarios live: the folder scenarios/ beside the
// mission file, one NAME.toml each. The one answer for `strata run
// --scenario NAME`, `strata vehicle --mission`, and the studio's list.
#include <filesystem>
#include <string>
#include <vector>

namespace strata::run {

// scenarios/ beside the mission, built from its path alone (nothing is
// looked at; the folder need not exist). A relative mission gives a
// relative folder: "tank/tank.coral" -> "tank/scenarios", "tank.coral" ->
// "scenarios".
std::filesystem::path scenarios_folder(const std::string& mission);

// The file of scenario `name` of the mission: scenarios_folder(mission) /
// "NAME.toml" (not looked at; `name` is taken as given).
std::filesystem::path scenario_path(const std::string& mission, const std::string& name);

// The scenarios in `folder`: NAME for each NAME.toml there that is a
// regular file (a link is followed), sorted. None when the folder is
// missing or cannot be read. Callers that confine files (the studio) check
// each name's file themselves.
std::vector<std::string> scenario_names_in(const std::filesystem::path& folder);

}  // namespace strata::run
