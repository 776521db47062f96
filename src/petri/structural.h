#pragma once
// Cheap structural arguments that settle a question (predicate.h) without
// exploring any marking. Each answer comes with the reason, for people.
// Implemented, each a proof, never a guess:
//
//   deadlock   never, when some transition has no input place (it is
//              enabled in every marking).
//   EF φ       never, when φ is false on every marking within the place
//              bounds below (so AG !φ holds). Bounds of place p, valid in
//              every reachable marking:
//                - at most y.M0 / y(p) for every P-semiflow y covering p;
//                - at most M0(p) when no transition increases p;
//                - at least M0(p) when no transition decreases p.
//
// Not implemented: the state equation (it needs an integer program) and
// siphon/trap arguments for deadlock freedom.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "petri/net.h"
#include "petri/predicate.h"

namespace strata::petri {

struct PlaceRange {
  std::int64_t low = 0;
  std::optional<std::int64_t> high;  // none: no bound known
};

// Bounds on every place in every reachable marking. P-semiflows are
// computed only on nets up to a size (places * (places + transitions) up
// to 2^21 cells); larger nets get the other two bounds only.
std::vector<PlaceRange> structural_ranges(const Net& net);

struct StructuralAnswer {
  bool yes = false;    // the question's answer (deadlock: one is reachable; EF: reachable)
  std::string reason;  // why, in words
};

// The deadlock question, when a structural argument settles it.
std::optional<StructuralAnswer> deadlock_by_structure(const Net& net);

// EF target, when the place ranges show target false in every reachable
// marking (answer: no).
std::optional<StructuralAnswer> reachable_by_structure(const Net& net, const Predicate& target,
                                                       const std::vector<PlaceRange>& ranges);

}  // namespace strata::petri
