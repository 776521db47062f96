#pragma once
// The reachability graph of a small net kept whole: every marking, every
// edge, and each state's breadth-first parent, so a property that fails can
// be shown by the shortest firing sequence that reaches it. Meant for
// mission nets (hundreds to a few hundred thousand markings); the explorer
// (explorer.h) is the one for large nets, and keeps no edges.
//
// Semantics: plain P/T interleaving (every enabled transition may fire;
// priorities are not applied), except that a marking with a token in a
// terminal place has no successors: the CORAL Engine ends a phase as soon
// as one of its exits is marked; and that urgent transitions (a CORAL
// guard's pre-emption, coral/guards.h), when one is enabled, are the only
// ones that may fire: those of the highest priority among the enabled
// urgent ones.
//
// Unboundedness: when a new marking that is not terminal covers one of its
// own ancestors (>= in every place, > in some), the firing sequence between
// them can repeat for ever (Karp and Miller), so the net is unbounded; the
// exploration stops there, with the two states recorded. Only the last 512
// ancestors are compared (a bound on the cost per state); a longer cycle is
// stopped by the state limit instead.
//
// A stopped exploration leaves the state it was expanding, and every later
// one, unexplored: no successors, not to be taken for a deadlock.
//
// Threads: none; build_reach_graph is a pure function.
#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "petri/net.h"

namespace strata::petri {

using StateId = std::uint32_t;
inline constexpr StateId kNoState = 0xffffffffu;

struct ReachOptions {
  std::vector<PlaceId> terminal_places;
  // Stop (complete = false) after this many markings.
  std::uint64_t max_states = 1'000'000;
  // Stop before the graph would need more bytes (0: no limit). Counted: the
  // markings, parents, edges and index as allocated, a vector's old and new
  // arrays while it grows, and what a verifier's passes over the graph add
  // (predecessor lists: 8 bytes per edge and 16 per state).
  std::size_t max_memory_bytes = 0;
  // Stop once the clock passes it.
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
  // By TransitionId, or empty: none is urgent.
  std::vector<bool> urgent = {};
};

struct ReachEdge {
  TransitionId transition;
  StateId target;
};

struct Unbounded {
  StateId state;     // the covering marking (stored, its parent chain leads to it)
  StateId ancestor;  // the marking it covers, on that chain
};

class ReachGraph {
 public:
  std::size_t state_count() const { return parent_.size(); }
  std::size_t edge_count() const { return edges_.size(); }
  // Bytes held, as counted against max_memory_bytes (passes excluded).
  std::size_t memory_bytes() const;
  std::span<const Tokens> marking(StateId s) const { return {markings_.data() + std::size_t{s} * places_, places_}; }
  // Successors of an explored state (none for a terminal or unexplored one).
  std::span<const ReachEdge> successors(StateId s) const;
  bool explored(StateId s) const { return s < explored_; }
  bool terminal(StateId s) const;
  // The breadth-first parent and the transition fired from it (kNoState at
  // the initial marking, state 0).
  StateId parent(StateId s) const { return parent_[s]; }
  TransitionId via(StateId s) const { return via_[s]; }
  // The shortest firing sequence from the initial marking to s.
  std::vector<TransitionId> path_to(StateId s) const;

  bool complete() const { return complete_; }
  const std::string& stopped_why() const { return stopped_why_; }
  const std::optional<Unbounded>& unbounded() const { return unbounded_; }

 private:
  friend ReachGraph build_reach_graph(const Net& net, const ReachOptions& options);
  std::size_t places_ = 0;
  std::vector<Tokens> markings_;  // state-major
  std::vector<StateId> parent_;
  std::vector<TransitionId> via_;
  std::vector<std::size_t> edge_begin_;  // explored states + 1
  std::vector<ReachEdge> edges_;
  std::vector<bool> is_terminal_place_;
  StateId explored_ = 0;
  bool complete_ = true;
  std::string stopped_why_;
  std::optional<Unbounded> unbounded_;
};

ReachGraph build_reach_graph(const Net& net, const ReachOptions& options = {});

}  // namespace strata::petri
