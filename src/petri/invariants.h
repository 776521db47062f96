#pragma once
// P-invariants of a net: weightings y of the places with y.C = 0, so that
// y.M is the same in every reachable marking M. computed as the minimal
// P-semiflows (y >= 0, smallest supports, entries with no common divisor) by
// the Farkas algorithm over the incidence matrix C = Post - Pre.
//
// A place in the support of a semiflow y is bounded by y.M0 / y(p) whatever
// fires; a net covered by semiflows is structurally bounded.
//
// Memory stays linear in the net where the net is sparse:
//  1. Contraction: a transition whose column of C is -w at one place and +w
//     at another (one input, one output, the same weight: a step of a
//     chain) merges the two places' rows into one (y = the sum of both).
//     Every row is then a group of places, the groups partition the places,
//     and no support holds another, so no minimality test is needed. A
//     chain of any length becomes one row, in time O(n log n).
//  2. What is left is cut into connected components (groups linked by the
//     remaining columns); a minimal semiflow lies in one.
//  3. Farkas on each component, with sparse rows, taking first the column
//     that makes the fewest new rows.
// The number of minimal semiflows can grow exponentially with the net (a
// chain of n fork/join pairs has 2^n); the computation stops (complete =
// false, stopped_why says which limit) past max_rows rows in a component,
// max_work entries touched (about a second for the default), the memory
// limit (the rows' bytes) or the deadline.
//
// Threads: none; pure functions.
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "petri/net.h"

namespace strata::petri {

struct Semiflow {
  std::vector<std::pair<PlaceId, std::uint64_t>> weights;  // the support, by PlaceId
  std::uint64_t constant = 0;                              // y.M0
};

struct Semiflows {
  std::vector<Semiflow> flows;  // sorted by their weights (first place first)
  bool complete = true;         // false: a limit stopped the computation; flows is then empty
  std::string stopped_why;      // when not complete: "more than 2000 rows", ...
  // By PlaceId: true when some semiflow's support holds the place.
  std::vector<bool> covered;
};

struct SemiflowLimits {
  std::size_t max_rows = 2000;           // rows of one component at one step
  std::uint64_t max_work = 200'000'000;  // matrix entries touched
  std::size_t max_memory_bytes = 0;      // the rows' bytes (0: no limit)
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
};

Semiflows p_semiflows(const Net& net, const SemiflowLimits& limits);
Semiflows p_semiflows(const Net& net, std::size_t max_rows = 2000, std::uint64_t max_work = 200'000'000);

// True when y.C = 0 for the weights (by PlaceId, missing = 0).
bool is_p_invariant(const Net& net, const std::vector<std::pair<PlaceId, std::uint64_t>>& weights);

}  // namespace strata::petri
