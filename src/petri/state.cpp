#include "petri/state.h"

#include <algorithm>
#include <bit>
#include <cassert>

namespace strata::petri {

EnabledSet::EnabledSet(const Net& net)
    : rank_(net.transition_count()), by_rank_(net.transition_count()), pos_(net.transition_count(), kAbsent) {
  const std::size_t n = net.transition_count();
  for (TransitionId t = 0; t < n; ++t) by_rank_[t] = t;
  std::stable_sort(by_rank_.begin(), by_rank_.end(),
                   [&](TransitionId a, TransitionId b) { return net.priority(a) > net.priority(b); });
  for (std::uint32_t r = 0; r < n; ++r) rank_[by_rank_[r]] = r;
  std::size_t bits = std::max<std::size_t>(n, 1);
  std::size_t total = 0;
  do {
    std::size_t words = (bits + 63) / 64;
    level_begin_.push_back(static_cast<std::uint32_t>(total));
    total += words;
    bits = words;
  } while (bits > 1);
  bits_.assign(total, 0);
}

void EnabledSet::insert(TransitionId t) {
  if (pos_[t] != kAbsent) return;
  pos_[t] = static_cast<std::uint32_t>(dense_.size());
  dense_.push_back(t);
  std::size_t i = rank_[t];
  for (std::uint32_t begin : level_begin_) {
    std::uint64_t& word = bits_[begin + i / 64];
    bool was_empty = word == 0;
    word |= std::uint64_t{1} << (i % 64);
    if (!was_empty) break;
    i /= 64;
  }
}

void EnabledSet::erase(TransitionId t) {
  std::uint32_t p = pos_[t];
  if (p == kAbsent) return;
  TransitionId last = dense_.back();
  dense_[p] = last;
  pos_[last] = p;
  dense_.pop_back();
  pos_[t] = kAbsent;
  std::size_t i = rank_[t];
  for (std::uint32_t begin : level_begin_) {
    std::uint64_t& word = bits_[begin + i / 64];
    word &= ~(std::uint64_t{1} << (i % 64));
    if (word != 0) break;
    i /= 64;
  }
}

std::optional<TransitionId> EnabledSet::first() const {
  if (dense_.empty()) return std::nullopt;
  std::size_t i = 0;
  for (std::size_t l = level_begin_.size(); l-- > 0;) {
    std::uint64_t word = bits_[level_begin_[l] + i];
    assert(word != 0);
    i = i * 64 + static_cast<std::size_t>(std::countr_zero(word));
  }
  return by_rank_[i];
}

std::vector<TransitionId> EnabledSet::sorted() const {
  std::vector<TransitionId> out(dense_);
  std::sort(out.begin(), out.end(), [&](TransitionId a, TransitionId b) { return rank_[a] < rank_[b]; });
  return out;
}

std::size_t EnabledSet::memory_bytes() const {
  std::size_t n =
      (rank_.capacity() + by_rank_.capacity() + dense_.capacity() + pos_.capacity()) * sizeof(std::uint32_t);
  return n + bits_.capacity() * sizeof(std::uint64_t) + level_begin_.capacity() * sizeof(std::uint32_t);
}

State::State(const Net& net) : State(net, net.initial_marking()) {}

State::State(const Net& net, Marking marking)
    : net_(&net), marking_(std::move(marking)), missing_(net.transition_count(), 0), enabled_(net) {
  assert(marking_.size() == net.place_count());
  for (TransitionId t = 0; t < net.transition_count(); ++t) {
    for (const Arc& a : net.inputs(t)) {
      if (marking_[a.node] < a.weight) ++missing_[t];
    }
    if (missing_[t] == 0) enabled_.insert(t);
  }
}

void State::set_tokens(PlaceId p, Tokens value) {
  const Tokens old = marking_[p];
  marking_[p] = value;
  for (const Arc& r : net_->readers(p)) {
    const bool was_ok = old >= r.weight;
    const bool now_ok = value >= r.weight;
    if (was_ok == now_ok) continue;
    if (now_ok) {
      if (--missing_[r.node] == 0) enabled_.insert(r.node);
    } else {
      if (missing_[r.node]++ == 0) enabled_.erase(r.node);
    }
  }
}

core::Error State::overflow(PlaceId p) const {
  return core::make_error(core::ErrorCode::Overflow, "place '" + std::string(net_->place_name(p)) + "' would exceed " +
                                                         std::to_string(kMaxTokens) + " tokens");
}

core::Result<void> State::fire(TransitionId t) {
  assert(is_enabled(t));
  for (const Arc& a : net_->outputs(t)) {
    // Conservative: ignores tokens a self-loop would take first.
    if (marking_[a.node] > kMaxTokens - a.weight) {
      return overflow(a.node);
    }
  }
  for (const Arc& a : net_->inputs(t)) set_tokens(a.node, marking_[a.node] - a.weight);
  for (const Arc& a : net_->outputs(t)) set_tokens(a.node, marking_[a.node] + a.weight);
  return {};
}

core::Result<void> State::add_tokens(PlaceId p, Tokens n) {
  if (marking_[p] > kMaxTokens - n) {
    return overflow(p);
  }
  if (n != 0) set_tokens(p, marking_[p] + n);
  return {};
}

void State::remove_tokens(PlaceId p, Tokens n) {
  assert(marking_[p] >= n);
  if (n != 0) set_tokens(p, marking_[p] - n);
}

std::size_t State::memory_bytes() const {
  return sizeof(*this) + marking_.capacity() * sizeof(Tokens) + missing_.capacity() * sizeof(std::uint32_t) +
         enabled_.memory_bytes();
}

}  // namespace strata::petri
