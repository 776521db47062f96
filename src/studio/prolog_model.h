#pragma once
// The PROLOG model of docs/studio.md (GET /api/mission of a .pl file): the
// rules as text, read-only, checked as `strata check` does on the process's
// one PROLOG thread, with SWI-Prolog's messages as diagnostics.
#include <string>

#include <nlohmann/json.hpp>

#include "studio/sandbox.h"
#include "tactical/catalogue.h"

namespace strata::studio {

// The model of `relative` (inside the sandbox). `etag` is set to the
// version of the file read, and left empty when it could not be read
// ("check": "unreadable"). "check" is "busy" when a PROLOG run holds the
// engine: the text comes without a check.
nlohmann::json prolog_model(const Sandbox& sandbox, const tactical::Catalogue& catalogue, const std::string& relative,
                            std::string& etag);

}  // namespace strata::studio
