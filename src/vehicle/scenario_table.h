#pragma once
// A scenario from a TOML table already parsed (scenario.h describes the
// keys): for a reader that checks or completes the table itself, as a
// campaign does with a world file. Its users link toml++ themselves.
#include <string_view>

#include <toml++/toml.h>

#include "core/result.h"
#include "vehicle/scenario.h"

namespace strata::vehicle {

// Errors carry "path:line:col: message", located by the table's own nodes
// (a node inserted by the caller has no place: "path: message").
core::Result<Scenario> scenario_from_table(std::string_view path, const toml::table& root);

}  // namespace strata::vehicle
