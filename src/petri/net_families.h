#pragma once
// Parameterised P/T nets whose reachability graphs have closed forms, for
// tests and benchmarks of the explorer without outside data. They follow
// the Model Checking Contest's families of the same names (same places,
// transitions and arcs), so the counts in ../shared/pnml/ANSWERS.md hold:
//
//   dining_philosophers(n): 5n places, 5n transitions, 16n arcs; 3^n states
//   referendum(n):          3n+1 places, 2n+1 transitions, 5n+1 arcs; 3^n + 1 states
#include "petri/net.h"

namespace strata::petri {

// n philosophers around a table, a fork between each two. Philosopher i
// takes its left fork then its right, or its right then its left, eats and
// puts both back.
Net dining_philosophers(unsigned n);

// A vote is opened, then each of n voters votes yes or no, once.
Net referendum(unsigned n);

}  // namespace strata::petri
