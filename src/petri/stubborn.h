#pragma once
// Stubborn sets (partial-order reduction) for a depth-first search that
// looks for a deadlock or for a marking satisfying a predicate (question.h).
//
// A set S of transitions is stubborn at marking m when
//   (a) for every enabled t in S, every transition that reads an input
//       place of t is in S (so no transition outside S can disable t, and t
//       commutes with every sequence of transitions outside S);
//   (b) for every disabled t in S, some input place p of t with
//       m(p) < w(p, t) (its scapegoat) has every transition that increases
//       p in S (so t stays disabled while only transitions outside S fire).
// Then the first transition of S in any firing sequence from m is enabled at
// m and can be moved to the front, reaching the same marking.
//
// Deadlocks: S holds one enabled transition (the key): every path to a
// deadlock fires some transition of S, since the key stays enabled
// otherwise. Firing only S's enabled transitions keeps a shortest path to a
// deadlock one step shorter, so every deadlock stays reachable.
//
// EF φ, φ false at m: S also holds up(φ, m), transitions one of which every
// path making φ true must fire: for "x >= k" false, the transitions that
// increase x; for "x <= k", those that decrease it; for "a && b", the up
// set of one false conjunct; for "a || b", of all of them (φ is in negation
// normal form). The same argument keeps a marking satisfying φ reachable
// (Schmidt, "Stubborn sets for standard properties", ICATPN 1999; LoLA's
// reachability rule), with no cycle proviso: the distance to the goal
// drops at every step.
//
// Threads: one per instance (it keeps scratch arrays).
#include <cstdint>
#include <span>
#include <vector>

#include "petri/net.h"
#include "petri/predicate.h"

namespace strata::petri {

class StubbornSets {
 public:
  explicit StubbornSets(const Net& net);

  // The enabled transitions of a stubborn set at m for the deadlock question,
  // into out (cleared first). `enabled` lists m's enabled transitions (not
  // empty); `is_enabled` is indexed by TransitionId.
  void for_deadlock(std::span<const Tokens> m, std::span<const TransitionId> enabled,
                    const std::vector<char>& is_enabled, std::vector<TransitionId>& out);

  // The enabled transitions of a stubborn set at m for reaching `target`,
  // which is false at m. Empty when no firing can make it true.
  void for_reaching(const Predicate& target, std::span<const Tokens> m, const std::vector<char>& is_enabled,
                    std::vector<TransitionId>& out);

 private:
  // Adds t to the set under construction (when new) and to the worklist.
  void add(TransitionId t) {
    if (stamp_[t] == generation_) return;
    stamp_[t] = generation_;
    work_.push_back(t);
  }
  void add_changers(const Term& t, bool up);
  // Up(φ, m) of node i (false at m) into the set.
  void add_up(const Predicate& target, std::uint32_t i, std::span<const Tokens> m);
  // Closes the set under (a) and (b); collects its enabled members into out.
  // Stops early (returning false) once more than `limit` enabled members.
  bool close(std::span<const Tokens> m, const std::vector<char>& is_enabled, std::vector<TransitionId>& out,
             std::size_t limit);
  void next_generation();

  const Net& net_;
  // By transition: the transitions reading one of its input places.
  std::vector<std::uint32_t> conflict_begin_;
  std::vector<TransitionId> conflicts_;
  // By place: the transitions that increase / decrease it.
  std::vector<std::uint32_t> inc_begin_, dec_begin_;
  std::vector<TransitionId> inc_, dec_;
  std::vector<std::uint32_t> stamp_;
  std::uint32_t generation_ = 0;
  std::vector<TransitionId> work_;
  std::vector<TransitionId> best_;
};

}  // namespace strata::petri
