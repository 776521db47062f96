#include "petri/structural.h"

#include <algorithm>
#include <set>

#include <fmt/format.h>

#include "petri/invariants.h"

namespace strata::petri {

namespace {

// P-semiflows only on nets up to this many cells (as the explorer).
constexpr std::size_t kStructuralSemiflowCells = std::size_t{1} << 21;

struct Interval {
  std::int64_t low = 0;
  std::optional<std::int64_t> high;
};

Interval term_interval(const Term& t, const std::vector<PlaceRange>& ranges) {
  if (!t.is_place) return {t.constant, t.constant};
  return {ranges[t.place].low, ranges[t.place].high};
}

// Whether a comparison can hold for some values in the intervals.
bool compare_possible(CompareOp op, const Interval& a, const Interval& b) {
  const bool a_open = !a.high, b_open = !b.high;
  switch (op) {
    case CompareOp::Lt: return b_open || a.low < *b.high;
    case CompareOp::Le: return b_open || a.low <= *b.high;
    case CompareOp::Gt: return a_open || *a.high > b.low;
    case CompareOp::Ge: return a_open || *a.high >= b.low;
    case CompareOp::Eq: return (b_open || a.low <= *b.high) && (a_open || b.low <= *a.high);
    case CompareOp::Ne: return a_open || b_open || !(a.low == *a.high && b.low == *b.high && a.low == b.low);
  }
  return true;
}

bool possible(const Predicate& p, std::uint32_t i, const std::vector<PlaceRange>& ranges) {
  const PredicateNode& n = p.node(i);
  switch (n.kind) {
    case PredicateNode::Kind::True: return true;
    case PredicateNode::Kind::False: return false;
    case PredicateNode::Kind::Compare:
      return compare_possible(n.op, term_interval(n.lhs, ranges), term_interval(n.rhs, ranges));
    case PredicateNode::Kind::And:
      return std::all_of(n.kids.begin(), n.kids.end(), [&](std::uint32_t k) { return possible(p, k, ranges); });
    case PredicateNode::Kind::Or:
      return std::any_of(n.kids.begin(), n.kids.end(), [&](std::uint32_t k) { return possible(p, k, ranges); });
  }
  return true;
}

void places_of(const Predicate& p, std::uint32_t i, std::set<PlaceId>& out) {
  const PredicateNode& n = p.node(i);
  if (n.kind == PredicateNode::Kind::Compare) {
    if (n.lhs.is_place) out.insert(n.lhs.place);
    if (n.rhs.is_place) out.insert(n.rhs.place);
  }
  for (std::uint32_t k : n.kids) places_of(p, k, out);
}

}  // namespace

std::vector<PlaceRange> structural_ranges(const Net& net) {
  const std::size_t places = net.place_count();
  std::vector<PlaceRange> r(places);
  std::vector<bool> increased(places, false), decreased(places, false);
  for (TransitionId t = 0; t < net.transition_count(); ++t) {
    for (const Arc& a : net.inputs(t)) {
      if (net.incidence(a.node, t) < 0) decreased[a.node] = true;
    }
    for (const Arc& a : net.outputs(t)) {
      if (net.incidence(a.node, t) > 0) increased[a.node] = true;
    }
  }
  for (PlaceId p = 0; p < places; ++p) {
    const std::int64_t m0 = net.initial_marking()[p];
    if (!decreased[p]) r[p].low = m0;
    if (!increased[p]) r[p].high = m0;
  }
  if (places > 0 && places * (places + net.transition_count()) <= kStructuralSemiflowCells) {
    const Semiflows s = p_semiflows(net);
    for (const Semiflow& f : s.flows) {
      if (!is_p_invariant(net, f.weights)) continue;  // never expected; a wrong bound would give a wrong answer
      for (const auto& [p, w] : f.weights) {
        if (w == 0) continue;
        const auto bound = static_cast<std::int64_t>(f.constant / w);
        r[p].high = r[p].high ? std::min(*r[p].high, bound) : bound;
      }
    }
  }
  return r;
}

std::optional<StructuralAnswer> deadlock_by_structure(const Net& net) {
  for (TransitionId t = 0; t < net.transition_count(); ++t) {
    if (net.inputs(t).empty()) {
      return StructuralAnswer{false, fmt::format("transition '{}' has no input place: it is enabled in every marking",
                                                 net.transition_name(t))};
    }
  }
  return std::nullopt;
}

std::optional<StructuralAnswer> reachable_by_structure(const Net& net, const Predicate& target,
                                                       const std::vector<PlaceRange>& ranges) {
  if (possible(target, target.root(), ranges)) return std::nullopt;
  std::set<PlaceId> used;
  places_of(target, target.root(), used);
  std::string bounds;
  for (PlaceId p : used) {
    if (!bounds.empty()) bounds += ", ";
    bounds += ranges[p].high ? fmt::format("{} in [{}, {}]", net.place_name(p), ranges[p].low, *ranges[p].high)
                             : fmt::format("{} >= {}", net.place_name(p), ranges[p].low);
  }
  return StructuralAnswer{false, fmt::format("{} never holds within the bounds from P-invariants and from the "
                                             "places no transition raises or lowers: {}",
                                             target.to_string(net), bounds.empty() ? "(no place)" : bounds)};
}

}  // namespace strata::petri
