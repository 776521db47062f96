#pragma once
// The reachability graph of a P/T net, explored in full (no reductions):
// state and edge counts and the global properties the Model Checking
// Contest reports (docs/verification.md).
//
// Storage: a marking is packed into 64-bit words, each place in a bit field
// just wide enough for the most tokens seen there so far (a field that would
// overflow widens, and every stored marking is re-packed); the markings lie
// one after another in one array and a hash table of 32-bit indices finds
// them. Nothing is allocated per state. Breadth-first: the array is the
// queue. Liveness needs a second pass over the graph (Tarjan's strongly
// connected components, successors recomputed, not stored), run only when
// the answer is not already known (a deadlock, a dead transition).
//
// Threads: one.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "petri/net.h"

namespace strata::petri {

struct ExploreProgress {
  std::uint64_t states = 0;      // found so far
  std::uint64_t explored = 0;    // whose successors are known
  std::uint64_t edges = 0;
  std::size_t memory_bytes = 0;  // markings + hash table
};

struct ExploreOptions {
  // Stop (complete = false) once markings and hash table would need more.
  // 0: no limit.
  std::size_t max_memory_bytes = 0;
  // Stop after this many states (0: no limit).
  std::uint64_t max_states = 0;
  // Decide liveness (a second pass) when it is not already known.
  bool liveness = true;
  // Called about every progress_every explored states; returning false
  // stops the exploration (complete = false), e.g. on Ctrl-C.
  std::function<bool(const ExploreProgress&)> progress;
  std::uint64_t progress_every = 1u << 20;
};

struct ExploreResult {
  bool complete = true;     // false: stopped early (memory, states, progress); the counts are partial
  std::string stopped_why;  // when not complete
  std::uint64_t states = 0;
  std::uint64_t edges = 0;  // (marking, enabled transition) pairs
  Tokens max_tokens_in_place = 0;
  std::uint64_t max_tokens_per_marking = 0;
  bool deadlock = false;    // some reachable marking enables nothing
  bool one_safe = true;     // no reachable marking has 2 tokens in a place
  bool quasi_live = false;  // every transition fires somewhere
  std::optional<bool> live; // every transition can always fire again; unset if not decided
  std::vector<Tokens> place_bounds;         // by PlaceId: the most tokens seen there
  std::vector<bool> transition_fired;       // by TransitionId
  std::optional<std::uint64_t> first_deadlock;  // the state index (BFS order) of a deadlock
  std::size_t memory_bytes = 0;             // markings + hash table at the end
  std::size_t words_per_state = 0;          // 64-bit words one packed marking takes
};

ExploreResult explore(const Net& net, const ExploreOptions& options = {});

}  // namespace strata::petri
