#pragma once
// A marking of a Net with its enabled set kept up to date incrementally:
// firing t re-examines only the readers of the places in I(t) and O(t), so
// the cost of a firing depends on the arcs it touches, not on the net's size.
#include <cstdint>
#include <optional>
#include <vector>

#include "core/result.h"
#include "petri/net.h"

namespace strata::petri {

// A set of transitions ordered by rank (highest priority first, then lowest
// id), with O(log64 n) insert, erase and first(), and O(1) access to the
// i-th member in an arbitrary order (for a seeded random choice).
class EnabledSet {
 public:
  explicit EnabledSet(const Net& net);

  void insert(TransitionId t);
  void erase(TransitionId t);
  bool contains(TransitionId t) const { return pos_[t] != kAbsent; }
  std::size_t size() const { return dense_.size(); }
  bool empty() const { return dense_.empty(); }
  // The member of best rank: highest priority, then declaration order.
  std::optional<TransitionId> first() const;
  // Members in no particular order, stable until the next insert or erase.
  TransitionId at(std::size_t i) const { return dense_[i]; }
  // Members in rank order (allocates; for dumps and tests).
  std::vector<TransitionId> sorted() const;

  std::size_t memory_bytes() const;

 private:
  static constexpr std::uint32_t kAbsent = UINT32_MAX;
  std::vector<std::uint32_t> rank_;    // transition -> rank
  std::vector<TransitionId> by_rank_;  // rank -> transition
  // A hierarchical bitmap in one array: level 0 has one bit per rank, each
  // higher level one bit per non-zero word below. level_begin_[l] is the
  // first word of level l; the top level is one word.
  std::vector<std::uint64_t> bits_;
  std::vector<std::uint32_t> level_begin_;
  std::vector<TransitionId> dense_;
  std::vector<std::uint32_t> pos_;  // transition -> index in dense_, or kAbsent
};

class State {
 public:
  // Starts at the net's initial marking. The net must outlive the state.
  explicit State(const Net& net);
  State(const Net& net, Marking marking);

  const Net& net() const { return *net_; }
  const Marking& marking() const { return marking_; }
  Tokens tokens(PlaceId p) const { return marking_[p]; }

  const EnabledSet& enabled() const { return enabled_; }
  bool is_enabled(TransitionId t) const { return enabled_.contains(t); }

  // The paper's state transition function: x(p) - w(p,t) + w(t,p) for all p.
  // Precondition: t is enabled. Fails with Overflow, leaving the state as it
  // was, if a place would exceed kMaxTokens.
  core::Result<void> fire(TransitionId t);

  // Adds n tokens to p (marks carried by a message: the Engine's step 1).
  core::Result<void> add_tokens(PlaceId p, Tokens n);
  // Removes n tokens from p. Precondition: tokens(p) >= n.
  void remove_tokens(PlaceId p, Tokens n);

  std::size_t memory_bytes() const;

 private:
  void set_tokens(PlaceId p, Tokens value);
  core::Error overflow(PlaceId p) const;

  const Net* net_;
  Marking marking_;
  std::vector<std::uint32_t> missing_;  // per transition: input arcs not yet satisfied
  EnabledSet enabled_;
};

}  // namespace strata::petri
