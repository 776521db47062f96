#pragma once
// Internal to the verifier (verifier.cpp runs it, verifier_properties.cpp
// decides each property, verifier_trace.cpp turns states into counterexamples
// and names for people): one net's analysis net and its explored state space.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "coral/analysis.h"
#include "coral/verifier.h"
#include "petri/reach_graph.h"

namespace strata::coral::detail {

// The nets `root` calls through PHASE, directly or not, each before its
// callers, and `root` last; without a root, every net of the program. A cycle
// of calls, which the checker reports, is cut where found.
std::vector<std::size_t> callees_first(const Program& program, std::optional<std::size_t> root);

using petri::StateId;

std::string join(const std::vector<std::string>& items, std::string_view sep = ", ");

// The limits of one verification, as each step applies them.
struct StepLimits {
  std::uint64_t max_states = 0;
  std::size_t max_memory_bytes = 0;  // the process's resident memory; 0: none
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();

  // What a step starting now may allocate (0: no limit).
  std::size_t memory_for_step() const;
  bool past_deadline() const { return std::chrono::steady_clock::now() > deadline; }
};

struct ExploredNet {
  // Builds the analysis net of cn (with the exits of the phases in `known`)
  // and explores it, within the limits (out of memory: what was explored).
  ExploredNet(const Program& program, const CompiledNet& cn, const std::vector<PhaseExits>& known,
              const StepLimits& limits);

  const Program& program;
  const CompiledNet& cn;
  AnalysisNet an;
  petri::ReachGraph graph;
  std::vector<std::uint64_t> bounds;  // by place of an.net: the most tokens seen there

  std::uint64_t max_bound() const;
  // A mission net without exits ends when nothing is enabled; a phase
  // without exits never ends.
  bool ends_when_dead() const;
  // Edges into s, with `target` holding their source; built on first use.
  std::span<const petri::ReachEdge> predecessors(StateId s) const;
  // Every step that can still happen from s.
  std::set<petri::TransitionId> reachable_steps(StateId from) const;

  // Names for people (verifier_trace.cpp).
  const ActionSpec& action_of(petri::TransitionId t, std::size_t i) const;
  std::string place_label(petri::PlaceId p) const;
  std::string step_label(petri::TransitionId t) const;
  std::vector<std::string> labels(const std::set<petri::TransitionId>& steps) const;

  // Counterexamples (verifier_trace.cpp): the shortest run to s, or the
  // steps of `path` from the initial marking, which end at state s.
  Counterexample trace_to(StateId s) const;
  Counterexample trace_along(const std::vector<petri::TransitionId>& path, StateId s) const;

 private:
  mutable std::vector<std::size_t> pred_begin_;
  mutable std::vector<petri::ReachEdge> preds_;
};

// The properties, in report order (verifier_properties.cpp).
Property bounded(const ExploredNet& x);
Property one_safe(const ExploredNet& x);
Property no_dead(const ExploredNet& x);
Property no_deadlock(const ExploredNet& x);
Property can_always_end(const ExploredNet& x);
Property no_busy_cycle(const ExploredNet& x);
Property exits_exclusive(const ExploredNet& x);
// Nets with guards only: each guard can trip from every marking where it
// polls, and from every trip its handler reaches an exit.
Property guards_can_trip(const ExploredNet& x);
Property guard_handlers_end(const ExploredNet& x);
// Structural: the deepest chain of PHASE calls from cn, against
// kMaxPhaseDepth (a mission net runs at depth 0, a phase at 1 at least).
Property phase_depth(const Program& program, const CompiledNet& cn);

}  // namespace strata::coral::detail
