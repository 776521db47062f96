#pragma once
// The scenario's [world] and [seabed] tables (scenario.h describes them), for
// scenario.cpp. Internal to strata_vehicle_model.
#include <string_view>

#include <toml++/toml.h>

#include "core/result.h"
#include "vehicle/scenario.h"

namespace strata::vehicle {

// Reads [world] and [seabed] from root into s.world and s.seabed. Errors
// carry "path:line:col: message".
core::Result<void> parse_world(std::string_view path, const toml::table& root, Scenario& s);

}  // namespace strata::vehicle
