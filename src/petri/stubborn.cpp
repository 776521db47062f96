#include "petri/stubborn.h"

#include <algorithm>

namespace strata::petri {

namespace {
// The deletion algorithm may take this many times the budget of the
// component search (it tries each enabled transition in turn).
constexpr std::uint64_t kDeletionBudget = 4;
}  // namespace

StubbornSets::StubbornSets(const Net& net)
    : net_(net),
      stamp_(net.transition_count(), 0),
      fed_(net.transition_count(), 0),
      number_(net.transition_count(), 0),
      low_(net.transition_count(), 0),
      on_stack_(net.transition_count(), 0),
      reach_(net.transition_count(), 0) {
  const std::size_t places = net.place_count();
  const std::size_t transitions = net.transition_count();
  // One pass over each transition's arcs (Net::incidence would search them
  // once per pair): the sign of C(p, t) for every place t has an arc on, in
  // increasing TransitionId, and for each input arc whether t takes from its
  // place (C(p, t) < 0).
  struct Change {
    PlaceId place;
    TransitionId t;
    bool up;  // C(p, t) > 0, else < 0
  };
  std::vector<Change> changes;
  std::vector<char> takes;  // by input arc, transition by transition
  {
    std::vector<std::int64_t> change(places, 0);
    std::vector<TransitionId> input_of(places, UINT32_MAX);
    auto note = [&](TransitionId t, PlaceId p) {
      if (change[p] != 0) changes.push_back({p, t, change[p] > 0});
    };
    for (TransitionId t = 0; t < transitions; ++t) {
      for (const Arc& a : net.outputs(t)) change[a.node] = a.weight;
      for (const Arc& a : net.inputs(t)) {
        input_of[a.node] = t;
        change[a.node] -= a.weight;
        takes.push_back(change[a.node] < 0 ? 1 : 0);
        note(t, a.node);
      }
      for (const Arc& a : net.outputs(t)) {
        if (input_of[a.node] != t) note(t, a.node);
      }
      for (const Arc& a : net.inputs(t)) change[a.node] = 0;
      for (const Arc& a : net.outputs(t)) change[a.node] = 0;
    }
  }
  // By place, in increasing TransitionId: the transitions that increase it
  // (inc_) and decrease it (dec_).
  inc_begin_.assign(places + 1, 0);
  dec_begin_.assign(places + 1, 0);
  for (const Change& c : changes) ++(c.up ? inc_begin_ : dec_begin_)[c.place + 1];
  for (std::size_t p = 0; p < places; ++p) {
    inc_begin_[p + 1] += inc_begin_[p];
    dec_begin_[p + 1] += dec_begin_[p];
  }
  inc_.resize(inc_begin_[places]);
  dec_.resize(dec_begin_[places]);
  {
    std::vector<std::uint32_t> inc_next(inc_begin_.begin(), inc_begin_.end() - 1);
    std::vector<std::uint32_t> dec_next(dec_begin_.begin(), dec_begin_.end() - 1);
    for (const Change& c : changes) {
      if (c.up) {
        inc_[inc_next[c.place]++] = c.t;
      } else {
        dec_[dec_next[c.place]++] = c.t;
      }
    }
  }
  std::vector<std::uint32_t> seen(transitions, UINT32_MAX);
  needs_begin_.reserve(transitions + 1);
  needs_begin_.push_back(0);
  std::size_t arc = 0;
  for (TransitionId t = 0; t < transitions; ++t) {
    seen[t] = t;
    auto need = [&](TransitionId u) {
      if (seen[u] == t) return;
      seen[u] = t;
      needs_.push_back(u);
    };
    for (const Arc& in : net.inputs(t)) {
      for (std::uint32_t i = dec_begin_[in.node]; i < dec_begin_[in.node + 1]; ++i) need(dec_[i]);
      if (takes[arc++]) {
        for (const Arc& r : net.readers(in.node)) need(r.node);
      }
    }
    needs_begin_.push_back(static_cast<std::uint32_t>(needs_.size()));
  }
  build_reverse();
  // Breadth-first from the sink places (and the transitions without an
  // output place) back along the arcs: a place is one more than the
  // nearest transition taking from it, a transition the nearest of its
  // output places.
  sink_distance_.assign(transitions, UINT32_MAX);
  std::vector<std::uint32_t> place_distance(places, UINT32_MAX);
  std::vector<PlaceId> queue;
  for (PlaceId p = 0; p < places; ++p) {
    if (net.readers(p).empty()) {
      place_distance[p] = 0;
      queue.push_back(p);
    }
  }
  auto reach = [&](TransitionId t, std::uint32_t d) {
    if (sink_distance_[t] != UINT32_MAX) return;
    sink_distance_[t] = d;
    for (const Arc& in : net.inputs(t)) {
      if (place_distance[in.node] != UINT32_MAX) continue;
      place_distance[in.node] = d + 1;
      queue.push_back(in.node);
    }
  };
  for (TransitionId t = 0; t < transitions; ++t) {
    if (net.outputs(t).empty()) reach(t, 0);
  }
  for (std::size_t k = 0; k < queue.size(); ++k) {
    for (const Arc& w : net.writers(queue[k])) reach(w.node, place_distance[queue[k]]);
  }
}

void StubbornSets::next_generation() {
  if (++generation_ == 0) {  // wrapped: old stamps could collide
    std::fill(stamp_.begin(), stamp_.end(), 0);
    std::fill(fed_.begin(), fed_.end(), 0);
    std::fill(deleted_.begin(), deleted_.end(), 0);
    std::fill(needed_.begin(), needed_.end(), 0);
    std::fill(dead_.begin(), dead_.end(), 0);
    std::fill(options_stamp_.begin(), options_stamp_.end(), 0);
    generation_ = 1;
  }
  work_.clear();
  steps_ = 0;
}

std::span<const TransitionId> StubbornSets::needed_by(TransitionId t, std::span<const Tokens> m, bool enabled) const {
  if (enabled) return {needs_.data() + needs_begin_[t], needs_.data() + needs_begin_[t + 1]};
  // The scapegoat: an input place short of tokens whose increasing
  // transitions are already in the set, or the fewest of them not yet in
  // (then the fewest in all): a set that closes on itself stays small.
  PlaceId best = 0;
  std::uint64_t best_count = UINT64_MAX;
  for (const Arc& in : net_.inputs(t)) {
    if (m[in.node] >= in.weight) continue;
    std::uint64_t fresh = 0;
    for (std::uint32_t i = inc_begin_[in.node]; i < inc_begin_[in.node + 1]; ++i) {
      fresh += stamp_[inc_[i]] != generation_ ? 1 : 0;
    }
    const std::uint64_t count = (fresh << 32) | (inc_begin_[in.node + 1] - inc_begin_[in.node]);
    if (count < best_count) {
      best = in.node;
      best_count = count;
      if (count == 0) break;
    }
  }
  return {inc_.data() + inc_begin_[best], inc_.data() + inc_begin_[best + 1]};
}

void StubbornSets::close(std::span<const Tokens> m, const std::vector<char>& is_enabled,
                         std::vector<TransitionId>& out) {
  out.clear();
  for (std::size_t k = 0; k < work_.size(); ++k) {
    const TransitionId t = work_[k];
    if (is_enabled[t]) out.push_back(t);
    for (TransitionId u : needed_by(t, m, is_enabled[t] != 0)) add(u);
  }
}

std::uint64_t StubbornSets::for_deadlock(std::span<const Tokens> m, std::span<const TransitionId> enabled,
                                         const std::vector<char>& is_enabled, std::vector<TransitionId>& out,
                                         std::uint64_t max_work, TransitionId last) {
  // Tarjan over "u needs v" from every enabled transition (`last`, then
  // those it fed, then the rest). The components complete in reverse
  // topological order, each knowing whether its closure holds an enabled
  // transition (reach_); one with enabled members whose other successors
  // reach none closes a set whose enabled members are its own. The
  // smallest such set is kept: the first found among equals.
  next_generation();
  calls_.clear();
  out.clear();
  roots_.assign(enabled.begin(), enabled.end());
  std::sort(roots_.begin(), roots_.end());
  if (last != kNoTransition) {
    for (std::uint32_t i = raises_begin_[last]; i < raises_begin_[last + 1]; ++i) {
      for (const Arc& r : net_.readers(raises_[i])) fed_[r.node] = generation_;
    }
    const auto rank = [&](TransitionId t) { return t == last ? 0 : fed_[t] == generation_ ? 1 : 2; };
    std::stable_sort(roots_.begin(), roots_.end(), [&](TransitionId a, TransitionId b) { return rank(a) < rank(b); });
  }
  std::uint32_t counter = 0;
  std::size_t best = SIZE_MAX;
  auto visit = [&](TransitionId t) {
    ++steps_;
    stamp_[t] = generation_;
    number_[t] = low_[t] = counter++;
    on_stack_[t] = 1;
    reach_[t] = 0;
    work_.push_back(t);
    const auto next = needed_by(t, m, is_enabled[t] != 0);
    calls_.push_back({t, 0, static_cast<std::uint32_t>(next.size()), next.data()});
  };
  for (TransitionId root : roots_) {
    if (stamp_[root] == generation_) continue;
    if (best == 1) break;  // none smaller
    if (steps_ > max_work) break;
    visit(root);
    while (!calls_.empty()) {
      if (steps_ > max_work) {  // the best set so far, if any
        calls_.clear();
        break;
      }
      Call& c = calls_.back();
      if (c.next < c.end) {
        ++steps_;
        const TransitionId u = c.list[c.next++];
        if (stamp_[u] != generation_) {
          visit(u);
        } else if (on_stack_[u]) {
          low_[c.t] = std::min(low_[c.t], number_[u]);
        } else {
          if (reach_[u]) reach_[c.t] = 1;  // a completed component
        }
        continue;
      }
      const TransitionId t = c.t;
      calls_.pop_back();
      if (low_[t] != number_[t]) {
        Call& parent = calls_.back();  // t's component is not complete: the parent is in it
        low_[parent.t] = std::min(low_[parent.t], low_[t]);
        if (reach_[t]) reach_[parent.t] = 1;
        continue;
      }
      // The component: work_ from t to the top.
      std::size_t first = work_.size();
      bool outside = false;
      std::size_t own = 0;
      do {
        --first;
        on_stack_[work_[first]] = 0;
        outside = outside || reach_[work_[first]] != 0;
        own += is_enabled[work_[first]] ? 1 : 0;
      } while (work_[first] != t);
      if (own > 0 && !outside && own < best) {
        best = own;
        out.clear();
        for (std::size_t k = first; k < work_.size(); ++k) {
          if (is_enabled[work_[k]]) out.push_back(work_[k]);
        }
      }
      const char r = (outside || own > 0) ? 1 : 0;
      for (std::size_t k = first; k < work_.size(); ++k) reach_[work_[k]] = r;
      work_.resize(first);
      if (r && !calls_.empty()) reach_[calls_.back().t] = 1;
    }
  }
  if (out.empty()) {
    out.assign(enabled.begin(), enabled.end());
  } else if (out.size() > 1) {
    // The deletion algorithm on top: the transitions outside the set
    // first, which leaves at most its enabled ones, then its own.
    std::sort(out.begin(), out.end());
    roots_.clear();
    for (TransitionId t : enabled) {
      if (!std::binary_search(out.begin(), out.end(), t)) roots_.push_back(t);
    }
    std::sort(roots_.begin(), roots_.end());  // whatever order `enabled` came in
    roots_.insert(roots_.end(), out.begin(), out.end());
    work_.clear();
    shrink(m, enabled.size(), is_enabled, max_work == UINT64_MAX ? max_work : steps_ + kDeletionBudget * max_work);
    out.clear();
    for (TransitionId t : enabled) {
      if (deleted_[t] != generation_) out.push_back(t);
    }
  }
  std::sort(out.begin(), out.end(), [&](TransitionId a, TransitionId b) {
    return sink_distance_[a] != sink_distance_[b] ? sink_distance_[a] < sink_distance_[b] : a < b;
  });
  return steps_;
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

std::uint64_t StubbornSets::for_reaching(const Predicate& target, std::span<const Tokens> m,
                                         const std::vector<char>& is_enabled, std::vector<TransitionId>& out) {
  next_generation();
  add_up(target, target.root(), m);
  close(m, is_enabled, out);
  return steps_;
}

}  // namespace strata::petri
