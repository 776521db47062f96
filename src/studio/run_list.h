#pragma once
// GET /api/runs (docs/studio.md): the mission logs of studio runs, found by
// their names in the runs/ folders under the sandbox.
#include <string>

#include <nlohmann/json.hpp>

#include "studio/sandbox.h"

namespace strata::studio {

// {"runs": [{"path", "mission_file", "started", "bytes"}, ...]}, newest
// first: the logs in runs/ beside `mission` (relative, already resolved
// inside the sandbox) named for its file name (or, as before 26 November
// 2026, for its stem), or every runs/*.jsonl when `mission` is empty.
nlohmann::json run_list(const Sandbox& sandbox, const std::string& mission);

}  // namespace strata::studio
