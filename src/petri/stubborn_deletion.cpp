// The deletion algorithm for the deadlock question (stubborn.h).
#include <algorithm>

#include "petri/stubborn.h"

namespace strata::petri {

void StubbornSets::build_reverse() {
  const std::size_t transitions = net_.transition_count();
  // Who needs u (rule a), and the places u increases, by transition.
  rneeds_begin_.assign(transitions + 1, 0);
  for (TransitionId u : needs_) ++rneeds_begin_[u + 1];
  for (std::size_t t = 0; t < transitions; ++t) rneeds_begin_[t + 1] += rneeds_begin_[t];
  rneeds_.resize(needs_.size());
  std::vector<std::uint32_t> next(rneeds_begin_.begin(), rneeds_begin_.end() - 1);
  for (TransitionId t = 0; t < transitions; ++t) {
    for (std::uint32_t i = needs_begin_[t]; i < needs_begin_[t + 1]; ++i) rneeds_[next[needs_[i]]++] = t;
  }
  raises_begin_.assign(transitions + 1, 0);
  for (TransitionId u : inc_) ++raises_begin_[u + 1];
  for (std::size_t t = 0; t < transitions; ++t) raises_begin_[t + 1] += raises_begin_[t];
  raises_.resize(inc_.size());
  next.assign(raises_begin_.begin(), raises_begin_.end() - 1);
  for (PlaceId p = 0; p + 1 < inc_begin_.size(); ++p) {
    for (std::uint32_t i = inc_begin_[p]; i < inc_begin_[p + 1]; ++i) raises_[next[inc_[i]]++] = p;
  }
  deleted_.assign(transitions, 0);
  options_.assign(transitions, 0);
  options_stamp_.assign(transitions, 0);
  needed_.assign(transitions, 0);
  dead_.assign(inc_begin_.size() - 1, 0);
}

std::uint32_t StubbornSets::options_of(TransitionId t, std::span<const Tokens> m) {
  if (options_stamp_[t] != generation_) {
    std::uint32_t n = 0;
    for (const Arc& in : net_.inputs(t)) n += m[in.node] < in.weight && dead_[in.node] != generation_ ? 1 : 0;
    options_stamp_[t] = generation_;
    options_[t] = n;
    ++steps_;
  }
  return options_[t];
}

// Deletes t0 and whatever then breaks rule (a) or (b); every deletion is
// logged for undo. Returns the enabled transitions deleted, or `alive` as
// soon as it is clear that none will be left (the caller undoes it all, so
// the rest of the cascade, often most of the net, is not followed): when
// the last one goes, or when a transition every stubborn set left holds
// (one whose own deletion was undone: needed_) goes.
std::size_t StubbornSets::delete_from(TransitionId t0, std::span<const Tokens> m, const std::vector<char>& is_enabled,
                                      std::size_t alive) {
  std::size_t enabled_gone = 0;
  bool doomed = false;
  auto remove = [&](TransitionId t) {
    doomed = doomed || needed_[t] == generation_;
    deleted_[t] = generation_;
    log_.push_back({Undo::Kind::Transition, t, 0});
    work_.push_back(t);
  };
  remove(t0);
  while (!work_.empty()) {
    if (doomed) {
      work_.clear();
      return alive;
    }
    const TransitionId u = work_.back();
    work_.pop_back();
    ++steps_;
    if (is_enabled[u] && ++enabled_gone == alive) {
      work_.clear();
      break;
    }
    // Rule (a): an enabled transition needing u goes.
    for (std::uint32_t i = rneeds_begin_[u]; i < rneeds_begin_[u + 1]; ++i) {
      ++steps_;
      const TransitionId t = rneeds_[i];
      if (is_enabled[t] && deleted_[t] != generation_) remove(t);
    }
    // Rule (b): a place u raises is no scapegoat any more.
    for (std::uint32_t i = raises_begin_[u]; i < raises_begin_[u + 1]; ++i) {
      const PlaceId p = raises_[i];
      if (dead_[p] == generation_) continue;
      dead_[p] = generation_;
      log_.push_back({Undo::Kind::Place, p, 0});
      for (const Arc& r : net_.readers(p)) {
        ++steps_;
        const TransitionId t = r.node;
        if (is_enabled[t] || m[p] >= r.weight || deleted_[t] == generation_) continue;
        const bool fresh = options_stamp_[t] != generation_;
        const std::uint32_t before = options_of(t, m);
        if (fresh) {  // counted with p already dead
          log_.push_back({Undo::Kind::Fresh, t, 0});
          if (before == 0) remove(t);
          continue;
        }
        log_.push_back({Undo::Kind::Options, t, before});
        if (--options_[t] == 0) remove(t);
      }
    }
  }
  return enabled_gone;
}

void StubbornSets::undo_to(std::size_t mark) {
  while (log_.size() > mark) {
    const Undo u = log_.back();
    log_.pop_back();
    switch (u.kind) {
      case Undo::Kind::Transition: deleted_[u.node] = 0; break;
      case Undo::Kind::Place: dead_[u.node] = 0; break;
      case Undo::Kind::Options: options_[u.node] = u.value; break;
      case Undo::Kind::Fresh: options_stamp_[u.node] = 0; break;
    }
  }
}

void StubbornSets::shrink(std::span<const Tokens> m, std::size_t enabled, const std::vector<char>& is_enabled,
                          std::uint64_t max_work) {
  log_.clear();
  std::size_t alive = enabled;
  for (TransitionId t0 : roots_) {
    if (alive == 1 || steps_ > max_work) break;
    if (deleted_[t0] == generation_) continue;
    const std::size_t mark = log_.size();
    const std::size_t gone = delete_from(t0, m, is_enabled, alive);
    if (gone == alive) {
      undo_to(mark);  // every stubborn set left holds t0
      needed_[t0] = generation_;
    } else {
      alive -= gone;
    }
  }
}

}  // namespace strata::petri
