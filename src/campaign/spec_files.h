#pragma once
// The files a campaign spec names for every case (docs/campaigns.md):
// `params`, the vehicle's parameter file, and `world`, a scenario's world.
// Each is read and checked as the spec is, so that a bad file is the spec's
// error, located at its key.
#include <toml++/toml.h>

#include "campaign/spec.h"
#include "core/toml_reader.h"

namespace strata::campaign {

// params = "FILE": the vehicle every case starts from (spec.params,
// params_resolved, base_params); problems added to errors.
void read_params(core::TomlErrors& errors, const toml::table& root, Spec& spec);

// world = "FILE": a scenario whose [world], [seabed] and [vehicle] every
// case runs in (spec.world, world_toml); the faults are the families'.
void read_world(core::TomlErrors& errors, const toml::table& root, Spec& spec);

}  // namespace strata::campaign
