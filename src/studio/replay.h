#pragma once
// A finished run, from its mission log (JSON Lines, docs/architecture.md),
// as the events a live page receives (docs/studio.md), with the marking of
// each instance rebuilt after every firing and every mark, for the replay
// slider.
#include <string>

#include <nlohmann/json.hpp>

#include "core/result.h"

namespace strata::studio {

// {"mission": path, "events": [{"event": name, "data": {...}}, ...]}.
// A line that is not JSON is an InvalidInput error naming its line number.
core::Result<nlohmann::json> replay_from_log(const std::string& log_text);

}  // namespace strata::studio
