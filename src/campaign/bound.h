#pragma once
// A campaign's proven bounds (docs/campaigns.md, "Cross-checking a proven
// bound"): for an expectation set's `bound` and a case's mission, the timing
// analysis's worst case (coral/timing.h), made once per mission, question
// and vehicle ascent in a process and kept for its other cases.
#include "campaign/expectations.h"
#include "campaign/spec.h"

namespace strata::campaign {

// The depth the ascent estimate starts from (a bound to the surface): the
// set's max_depth_m, which the campaign holds every case to, else the
// depth `strata verify --bound` assumes.
double bound_depth_m(const ExpectationSet& set);

// The analysis's answer for `set.bound` (which must be set) on the spec's
// mission `mission`, the vehicle being `params`. PROLOG rules have none:
// measured_only. Thread-safe.
BoundProof proven_bound(const Spec& spec, std::size_t mission, const ExpectationSet& set,
                        const vehicle::VehicleParams& params);

}  // namespace strata::campaign
