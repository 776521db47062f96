#pragma once
// P-invariants of a net: weightings y of the places with y.C = 0, so that
// y.M is the same in every reachable marking M. computed as the minimal
// P-semiflows (y >= 0, smallest supports, entries with no common divisor) by
// the Farkas algorithm over the incidence matrix C = Post - Pre.
//
// A place in the support of a semiflow y is bounded by y.M0 / y(p) whatever
// fires; a net covered by semiflows is structurally bounded.
//
// The number of minimal semiflows can grow exponentially with the net (a
// chain of n fork/join pairs has 2^n); the computation stops (complete =
// false) past max_rows rows or max_work matrix entries touched, a bound on
// its time (about a second for the default).
#include <cstdint>
#include <vector>

#include "petri/net.h"

namespace strata::petri {

struct Semiflow {
  std::vector<std::pair<PlaceId, std::uint64_t>> weights;  // the support, by PlaceId
  std::uint64_t constant = 0;                              // y.M0
};

struct Semiflows {
  std::vector<Semiflow> flows;  // sorted by their first place, then weights
  bool complete = true;         // false: the row limit stopped the computation
  // By PlaceId: true when some semiflow's support holds the place.
  std::vector<bool> covered;
};

Semiflows p_semiflows(const Net& net, std::size_t max_rows = 2000, std::uint64_t max_work = 200'000'000);

// True when y.C = 0 for the weights (by PlaceId, missing = 0).
bool is_p_invariant(const Net& net, const std::vector<std::pair<PlaceId, std::uint64_t>>& weights);

}  // namespace strata::petri
