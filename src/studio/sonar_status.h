#pragma once
// GET /api/sonar (docs/studio.md): what the sonar folder of a run holds.
#include <filesystem>

#include <nlohmann/json.hpp>

namespace strata::studio {

// {"dir": bool, "latest": {"bytes", "mtime_ms"} or null, "frame": the last
// line of sonar.jsonl or null}; `dir` empty: a studio without sonar.
nlohmann::json sonar_status(const std::filesystem::path& dir);

}  // namespace strata::studio
