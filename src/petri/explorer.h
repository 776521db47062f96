#pragma once
// The reachability graph of a P/T net, explored in full (no reductions):
// state and edge counts and the global properties the Model Checking
// Contest reports (docs/verification.md).
//
// Storage: a marking is packed into 64-bit words, each place in a bit field.
// A field starts as wide as the place's initial tokens; one that would
// overflow widens (doubling) and every stored marking is re-packed. From
// 2^15 states on, a place covered by a P-semiflow y (y >= 0, y.C = 0) has a
// field as wide as its bound y.M0 / y(p), which never overflows (computing
// the P-semiflows costs more than a small graph). The markings are kept in
// the slots of an open-addressing hash table (linear probing, one cache miss
// per lookup; huge pages when the kernel allows; doubling without holding
// two full arrays); copies of the markings not explored yet, in 64 KB
// blocks, are the breadth-first queue. Nothing is allocated per state. The
// successors of the next queued state are computed and their slots
// prefetched before this state's lookups.
//
// Liveness needs a second pass, run only when the answer is not already
// known (a deadlock, a dead transition): a backward search from the initial
// marking (predecessors m - Post(t) + Pre(t), looked up in the table); when
// it reaches every state the graph is strongly connected and the net live.
// Otherwise Tarjan's strongly connected components (successors recomputed,
// not stored) decide: live iff every bottom component enables every
// transition. The pass's own arrays (a bit per table slot and 4 bytes per
// state for the backward search; about 10 bytes per slot for Tarjan) are
// freed when it ends and not counted in memory_bytes.
//
// Threads: one.
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "petri/net.h"

namespace strata::petri {

struct ExploreProgress {
  std::uint64_t states = 0;    // found so far
  std::uint64_t explored = 0;  // whose successors are known
  std::uint64_t edges = 0;
  std::size_t memory_bytes = 0;  // hash table (the markings) + queue
};

struct ExploreOptions {
  // Stop (complete = false) once the hash table (the markings) and the
  // queue would need more, counting a growing table at its peak (while the
  // old array is under 2 MB, both arrays; then the new one and two 2 MB
  // pages of the old); the liveness pass is not run (live unset) when its
  // arrays would not fit beside the table. 0: no limit.
  std::size_t max_memory_bytes = 0;
  // Stop (complete = false; or live unset, in the liveness pass) once the
  // clock passes it.
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
  // Stop after this many states (0: no limit).
  std::uint64_t max_states = 0;
  // Decide liveness (a second pass) when it is not already known.
  bool liveness = true;
  // The token counts and the transitions fired: max_tokens_in_place,
  // max_tokens_per_marking, one_safe, place_bounds, transition_fired,
  // quasi_live, and liveness, which needs them. Off, only complete,
  // stopped_why, states, edges, deadlock, first_deadlock and the memory are
  // meaningful (the rest keep their defaults, live unset): what a deadlock
  // question needs (question.h), a few percent faster.
  bool statistics = true;
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
  bool deadlock = false;                        // some reachable marking enables nothing
  bool one_safe = true;                         // no reachable marking has 2 tokens in a place
  bool quasi_live = false;                      // every transition fires somewhere
  std::optional<bool> live;                     // every transition can always fire again; unset if not decided
  std::string live_why;                         // when live is unset after a complete exploration: why
  std::vector<Tokens> place_bounds;             // by PlaceId: the most tokens seen there
  std::vector<bool> transition_fired;           // by TransitionId
  std::optional<std::uint64_t> first_deadlock;  // the state index (BFS order) of a deadlock
  std::size_t memory_bytes = 0;                 // hash table (the markings) + queue, allocated, at the end
  // The most the hash table and the queue held at once, a growing table's
  // old and new arrays counted as far as both were held (the liveness
  // pass's arrays are not counted).
  std::size_t peak_memory_bytes = 0;
  std::size_t words_per_state = 0;  // 64-bit words one packed marking takes
};

ExploreResult explore(const Net& net, const ExploreOptions& options = {});

}  // namespace strata::petri
