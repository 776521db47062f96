#include "petri/stubborn.h"

#include <algorithm>

namespace strata::petri {

namespace {

// Keys tried for the deadlock question at one marking: the smallest
// closure among them is kept.
constexpr std::size_t kStubbornKeysTried = 8;

}  // namespace

StubbornSets::StubbornSets(const Net& net) : net_(net), stamp_(net.transition_count(), 0) {
  const std::size_t places = net.place_count();
  const std::size_t transitions = net.transition_count();
  std::vector<std::uint32_t> seen(transitions, UINT32_MAX);
  conflict_begin_.reserve(transitions + 1);
  conflict_begin_.push_back(0);
  for (TransitionId t = 0; t < transitions; ++t) {
    for (const Arc& in : net.inputs(t)) {
      for (const Arc& r : net.readers(in.node)) {
        if (seen[r.node] == t) continue;
        seen[r.node] = t;
        conflicts_.push_back(r.node);
      }
    }
    conflict_begin_.push_back(static_cast<std::uint32_t>(conflicts_.size()));
  }
  inc_begin_.push_back(0);
  dec_begin_.push_back(0);
  for (PlaceId p = 0; p < places; ++p) {
    // Candidates: the transitions with an arc on p; the sign of C(p, t).
    std::vector<TransitionId> touching;
    for (const Arc& a : net.readers(p)) touching.push_back(a.node);
    for (const Arc& a : net.writers(p)) touching.push_back(a.node);
    std::sort(touching.begin(), touching.end());
    touching.erase(std::unique(touching.begin(), touching.end()), touching.end());
    for (TransitionId t : touching) {
      const std::int64_t c = net.incidence(p, t);
      if (c > 0) inc_.push_back(t);
      if (c < 0) dec_.push_back(t);
    }
    inc_begin_.push_back(static_cast<std::uint32_t>(inc_.size()));
    dec_begin_.push_back(static_cast<std::uint32_t>(dec_.size()));
  }
}

void StubbornSets::next_generation() {
  if (++generation_ == 0) {  // wrapped: old stamps could collide
    std::fill(stamp_.begin(), stamp_.end(), 0);
    generation_ = 1;
  }
  work_.clear();
}

bool StubbornSets::close(std::span<const Tokens> m, const std::vector<char>& is_enabled, std::vector<TransitionId>& out,
                         std::size_t limit) {
  out.clear();
  for (std::size_t k = 0; k < work_.size(); ++k) {
    const TransitionId t = work_[k];
    if (is_enabled[t]) {
      out.push_back(t);
      if (out.size() > limit) return false;
      for (std::uint32_t i = conflict_begin_[t]; i < conflict_begin_[t + 1]; ++i) add(conflicts_[i]);
      continue;
    }
    // The scapegoat: an input place short of tokens, with the fewest
    // transitions that increase it.
    PlaceId best = 0;
    std::uint32_t best_count = UINT32_MAX;
    for (const Arc& in : net_.inputs(t)) {
      if (m[in.node] >= in.weight) continue;
      const std::uint32_t count = inc_begin_[in.node + 1] - inc_begin_[in.node];
      if (count < best_count) {
        best = in.node;
        best_count = count;
        if (count == 0) break;
      }
    }
    for (std::uint32_t i = inc_begin_[best]; i < inc_begin_[best + 1]; ++i) add(inc_[i]);
  }
  return true;
}

void StubbornSets::for_deadlock(std::span<const Tokens> m, std::span<const TransitionId> enabled,
                                const std::vector<char>& is_enabled, std::vector<TransitionId>& out) {
  best_.clear();
  std::size_t best_size = enabled.size();
  bool found = false;
  const std::size_t tries = std::min(enabled.size(), kStubbornKeysTried);
  for (std::size_t k = 0; k < tries && best_size > 1; ++k) {
    next_generation();
    add(enabled[k]);
    // A set with as many enabled members as the best so far (or as all
    // of them) is no better.
    if (!close(m, is_enabled, out, best_size - 1)) continue;
    best_.swap(out);
    best_size = best_.size();
    found = true;
  }
  if (found) {
    out.swap(best_);
  } else {
    out.assign(enabled.begin(), enabled.end());
  }
}

void StubbornSets::add_changers(const Term& t, bool up) {
  if (!t.is_place) return;
  const auto& begin = up ? inc_begin_ : dec_begin_;
  const auto& list = up ? inc_ : dec_;
  for (std::uint32_t i = begin[t.place]; i < begin[t.place + 1]; ++i) add(list[i]);
}

void StubbornSets::add_up(const Predicate& target, std::uint32_t i, std::span<const Tokens> m) {
  const PredicateNode& n = target.node(i);
  switch (n.kind) {
    case PredicateNode::Kind::True:
    case PredicateNode::Kind::False: return;  // no firing changes a constant
    case PredicateNode::Kind::And:
      // One false conjunct is enough: take the first.
      for (std::uint32_t k : n.kids) {
        if (!target.holds(k, m)) {
          add_up(target, k, m);
          return;
        }
      }
      return;
    case PredicateNode::Kind::Or:
      for (std::uint32_t k : n.kids) add_up(target, k, m);
      return;
    case PredicateNode::Kind::Compare: break;
  }
  bool raise_lhs = false, lower_lhs = false;
  switch (n.op) {
    case CompareOp::Lt:
    case CompareOp::Le: lower_lhs = true; break;
    case CompareOp::Gt:
    case CompareOp::Ge: raise_lhs = true; break;
    case CompareOp::Eq: (n.lhs.value(m) < n.rhs.value(m) ? raise_lhs : lower_lhs) = true; break;
    case CompareOp::Ne: raise_lhs = lower_lhs = true; break;
  }
  // Raising the left side works like lowering the right one.
  if (raise_lhs) {
    add_changers(n.lhs, true);
    add_changers(n.rhs, false);
  }
  if (lower_lhs) {
    add_changers(n.lhs, false);
    add_changers(n.rhs, true);
  }
}

void StubbornSets::for_reaching(const Predicate& target, std::span<const Tokens> m, const std::vector<char>& is_enabled,
                                std::vector<TransitionId>& out) {
  next_generation();
  add_up(target, target.root(), m);
  close(m, is_enabled, out, SIZE_MAX);
}

}  // namespace strata::petri
