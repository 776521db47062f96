#pragma once
// The timing analysis's view of a vehicle (coral/timing.h): its primitives'
// reply bounds from the catalogue, and the ascent estimate from its
// parameters (docs/verification.md, "Reaction time").
#include <cstdint>

#include "coral/timing.h"
#include "tactical/catalogue.h"
#include "vehicle/params.h"

namespace strata::run {

// The options for a vehicle with catalogue `cat` (which must outlive them):
// its primitives' reply bounds, and the ascent estimate from depth_max_m.
coral::BoundOptions bound_options(const tactical::Catalogue& cat, double depth_max_m = 6.0,
                                  std::uint64_t max_states = coral::BoundOptions{}.max_states);

// From `exec surface` at depth_m to the vehicle at the surface, at most (an
// estimate from the vehicle's parameters, with a margin).
double ascent_estimate_s(const vehicle::VehicleParams& p, double depth_m);

}  // namespace strata::run
