#pragma once
// Stubborn sets (partial-order reduction) for a depth-first search that
// looks for a deadlock or for a marking satisfying a predicate (question.h).
//
// A set S of transitions is stubborn at marking m when
//   (a) for every enabled t in S, S holds every transition that decreases an
//       input place of t (it could disable t) and every transition with an
//       input place that t decreases (t could disable it); one that only
//       tests a place, or adds to it, commutes with t there;
//   (b) for every disabled t in S, some input place p of t with
//       m(p) < w(p, t) (its scapegoat) has every transition that increases
//       p in S (so t stays disabled while only transitions outside S fire).
// Then the first transition of S in any firing sequence from m is enabled at
// m and can be moved to the front, reaching the same marking: no transition
// outside S took tokens it needed, and it took none they needed.
//
// Deadlocks: S holds an enabled transition (every enabled member is a key):
// every path to a deadlock fires some transition of S, since the key stays
// enabled otherwise. Firing only S's enabled transitions keeps a shortest
// path to a deadlock one step shorter, so every deadlock stays reachable.
// The set is found in two stages (Valmari's two algorithms, combined):
//   1. Tarjan's strongly connected components over the graph "u in S needs
//      v in S" (the scapegoats chosen as it goes), from every enabled
//      transition: the one whose firing led to m first, then those it fed
//      (an input place it increased), then the rest in increasing
//      TransitionId. A component with enabled members whose other
//      successors reach no enabled transition closes a set whose enabled
//      members are its own; the one with the fewest is kept (one with a
//      single enabled member ends it). So of the sets with one enabled
//      transition the search keeps moving the part of the net that just
//      moved (persistence), and interleaves the independent parts less.
//   2. The deletion algorithm on top: start from every transition (a
//      stubborn set) and delete one enabled transition at a time, with
//      whatever then breaks a rule: an enabled transition needing a deleted
//      one; a disabled one whose every short input place lost an increasing
//      transition (so no scapegoat is left). A deletion that would leave no
//      enabled transition is undone. The enabled transitions outside stage
//      1's set are tried first (they all go: that set never needs them),
//      then its own: the result has at most its enabled members, and may
//      use other scapegoats than the ones stage 1 fixed.
// The scapegoat of a disabled transition in stage 1: a short input place
// whose increasing transitions are already in the graph, else the fewest
// not yet in, then the fewest in all. The enabled members come out in the
// order the search fires them: nearest a sink place first (one no
// transition takes from: where tokens stop, as in a deadlock), counted in
// transitions along the net's arcs, then increasing TransitionId
// (declaration order, as LoLA's). Where the set holds a decision, the
// search tries first the branch that ends soonest; in a net without sink
// places the order is declaration order.
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
  static constexpr TransitionId kNoTransition = UINT32_MAX;

  explicit StubbornSets(const Net& net);

  // Both return the work done: transitions taken into the set plus the
  // successors of theirs looked at (what the caller weighs against the
  // transitions pruned; question.cpp).
  //
  // The enabled transitions of a stubborn set at m for the deadlock question,
  // into out (cleared first), in the order to fire them (below). `enabled` lists
  // m's enabled transitions (not empty); `is_enabled` is indexed by
  // TransitionId; `last` is the transition whose firing led to m
  // (kNoTransition at the initial marking). Past max_work stage 1 stops
  // with the best set so far, or every enabled transition (a stubborn set
  // too) when it has none; stage 2 may take kDeletionBudget times max_work
  // more (stubborn.cpp).
  std::uint64_t for_deadlock(std::span<const Tokens> m, std::span<const TransitionId> enabled,
                             const std::vector<char>& is_enabled, std::vector<TransitionId>& out,
                             std::uint64_t max_work = UINT64_MAX, TransitionId last = kNoTransition);

  // The enabled transitions of a stubborn set at m for reaching `target`,
  // which is false at m. Empty when no firing can make it true.
  std::uint64_t for_reaching(const Predicate& target, std::span<const Tokens> m, const std::vector<char>& is_enabled,
                             std::vector<TransitionId>& out);

 private:
  // Adds t to the set under construction (when new) and to the worklist.
  void add(TransitionId t) {
    ++steps_;
    if (stamp_[t] == generation_) return;
    stamp_[t] = generation_;
    work_.push_back(t);
  }
  void add_changers(const Term& t, bool up);
  // Up(φ, m) of node i (false at m) into the set.
  void add_up(const Predicate& target, std::uint32_t i, std::span<const Tokens> m);
  // What t in S brings into S at m: for enabled t its needs (rule a), for
  // disabled t the transitions increasing its scapegoat (rule b).
  std::span<const TransitionId> needed_by(TransitionId t, std::span<const Tokens> m, bool enabled) const;
  // Closes the set under (a) and (b); collects its enabled members into out.
  void close(std::span<const Tokens> m, const std::vector<char>& is_enabled, std::vector<TransitionId>& out);
  void next_generation();

  const Net& net_;
  // By transition: what it needs in S when enabled (rule a), itself excluded.
  std::vector<std::uint32_t> needs_begin_;
  std::vector<TransitionId> needs_;
  // By place: the transitions that increase / decrease it.
  std::vector<std::uint32_t> inc_begin_, dec_begin_;
  std::vector<TransitionId> inc_, dec_;
  // By transition: the fewest transitions from its output to a sink place
  // (0: it outputs to one, or to nothing), UINT32_MAX when none is reached.
  std::vector<std::uint32_t> sink_distance_;
  std::vector<std::uint32_t> stamp_;  // == generation_: in the set (visited)
  std::vector<std::uint32_t> fed_;    // == generation_: fed by for_deadlock's `last`
  std::uint32_t generation_ = 0;
  std::vector<TransitionId> work_;  // the worklist; Tarjan's stack
  // Tarjan (for_deadlock), by transition: visit number, lowest number
  // reachable, on the stack.
  std::vector<std::uint32_t> number_, low_;
  std::vector<char> on_stack_;
  // By transition, once its component is complete: its closure holds an
  // enabled transition; before: one of its successors' closures outside
  // its component does.
  std::vector<char> reach_;
  std::vector<TransitionId> roots_;
  struct Call {
    TransitionId t;
    std::uint32_t next, end;  // its successors: (*list)[next, end)
    const TransitionId* list;
  };
  std::vector<Call> calls_;
  std::uint64_t steps_ = 0;  // the work of the current call

  // The deletion algorithm (stubborn_deletion.cpp).
  void build_reverse();
  std::uint32_t options_of(TransitionId t, std::span<const Tokens> m);
  std::size_t delete_from(TransitionId t0, std::span<const Tokens> m, const std::vector<char>& is_enabled,
                          std::size_t alive);
  void undo_to(std::size_t mark);
  // Deletes roots_ in turn (each with what then breaks a rule) while an
  // enabled transition is left; a deletion that would leave none is undone.
  void shrink(std::span<const Tokens> m, std::size_t enabled, const std::vector<char>& is_enabled,
              std::uint64_t max_work);
  std::vector<std::uint32_t> rneeds_begin_, raises_begin_;
  std::vector<TransitionId> rneeds_;
  std::vector<PlaceId> raises_;
  // By transition (== generation_: so): deleted; every stubborn set left
  // holds it (its deletion was undone). By place: no scapegoat any more.
  std::vector<std::uint32_t> deleted_, needed_, dead_, options_, options_stamp_;
  struct Undo {
    enum class Kind : std::uint8_t { Transition, Place, Options, Fresh } kind;
    std::uint32_t node, value;
  };
  std::vector<Undo> log_;
};

}  // namespace strata::petri
