#pragma once
// A campaign spec's vehicle parameter perturbations (docs/campaigns.md,
// "perturb"): the spec's and each family's `perturb` tables, read into axes
// over config/phoenix.toml's parameters.
#include <cstdint>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "campaign/spec.h"
#include "core/toml_reader.h"

namespace strata::campaign {

// perturb = { TABLE.KEY = AXIS, ... }: each a vehicle parameter's axis, in
// config/phoenix.toml's order; empty with the problems added to errors.
// `where` names the axes for sampling ("perturb", "FAMILY.perturb").
std::vector<Perturbation> read_perturb(core::TomlErrors& errors, const toml::node& node, const std::string& where,
                                       std::uint64_t sample_seed, std::uint64_t max_cases);

// Family f's perturbations: its own `perturb` over the spec's, every
// combination of those the rules between parameters name checked, set over
// base (the spec's parameter file, or the built-in parameters).
void read_family_perturb(core::TomlErrors& errors, const toml::table& t, Family& f,
                         const std::vector<Perturbation>& spec_perturb, const vehicle::VehicleParams& base,
                         std::uint64_t sample_seed, std::uint64_t max_cases);

}  // namespace strata::campaign
