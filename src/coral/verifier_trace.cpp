// One explored net's queries, its names for people, and counterexamples: the
// steps from the initial marking to a state, with what is marked and what is
// in flight there.
#include <algorithm>
#include <cctype>

#include <fmt/format.h>

#include "coral/verifier_internal.h"
#include "core/memory.h"

namespace strata::coral::detail {

std::string join(const std::vector<std::string>& items, std::string_view sep) {
  std::string s;
  for (const auto& i : items) s += (s.empty() ? "" : std::string(sep)) + i;
  return s;
}

std::size_t StepLimits::memory_for_step() const { return core::memory_left(max_memory_bytes); }

ExploredNet::ExploredNet(const Program& of_program, const CompiledNet& net, const std::vector<PhaseExits>& known,
                         const StepLimits& limits)
    : program(of_program), cn(net), an(build_analysis_net(of_program, net, known)) {
  petri::ReachOptions ro;
  ro.terminal_places = net.exits;
  ro.urgent = an.urgent;
  ro.max_states = limits.max_states;
  ro.max_memory_bytes = limits.memory_for_step();
  ro.deadline = limits.deadline;
  graph = petri::build_reach_graph(an.net, ro);
  bounds.assign(an.net.place_count(), 0);
  for (StateId s = 0; s < graph.state_count(); ++s) {
    auto m = graph.marking(s);
    for (std::size_t p = 0; p < m.size(); ++p) bounds[p] = std::max<std::uint64_t>(bounds[p], m[p]);
  }
}

// A mission net without exits ends when nothing is enabled; a phase
// without exits never ends.
bool ExploredNet::ends_when_dead() const { return cn.exits.empty() && cn.kind == ast::Net::Kind::Mission; }

// Edges into s, with `target` holding their source; built on first use.
std::span<const petri::ReachEdge> ExploredNet::predecessors(StateId s) const {
  if (pred_begin_.empty()) {
    const std::size_t n = graph.state_count();
    pred_begin_.assign(n + 1, 0);
    for (StateId q = 0; q < n; ++q) {
      for (const auto& e : graph.successors(q)) ++pred_begin_[e.target + 1];
    }
    for (std::size_t i = 0; i < n; ++i) pred_begin_[i + 1] += pred_begin_[i];
    preds_.resize(pred_begin_[n]);
    std::vector<std::size_t> at(pred_begin_.begin(), pred_begin_.end() - 1);
    for (StateId q = 0; q < n; ++q) {
      for (const auto& e : graph.successors(q)) preds_[at[e.target]++] = {e.transition, q};
    }
  }
  return {preds_.data() + pred_begin_[s], preds_.data() + pred_begin_[s + 1]};
}

// Every step that can still happen from s.
std::set<petri::TransitionId> ExploredNet::reachable_steps(StateId from) const {
  std::set<petri::TransitionId> steps;
  std::vector<bool> seen(graph.state_count(), false);
  std::vector<StateId> stack{from};
  seen[from] = true;
  while (!stack.empty()) {
    StateId s = stack.back();
    stack.pop_back();
    for (const auto& e : graph.successors(s)) {
      steps.insert(e.transition);
      if (!seen[e.target]) {
        seen[e.target] = true;
        stack.push_back(e.target);
      }
    }
  }
  return steps;
}

std::vector<std::string> ExploredNet::labels(const std::set<petri::TransitionId>& steps) const {
  std::set<std::string> names;
  for (auto t : steps) names.insert(step_label(t));
  return {names.begin(), names.end()};
}

std::uint64_t ExploredNet::max_bound() const {
  return bounds.empty() ? 0 : *std::max_element(bounds.begin(), bounds.end());
}

const ActionSpec& ExploredNet::action_of(petri::TransitionId t, std::size_t i) const { return cn.actions[t][i]; }

// A place for people: the mission's name, or the action waiting there.
std::string ExploredNet::place_label(petri::PlaceId p) const {
  const auto& o = an.places[p];
  if (o.place) return std::string(cn.net.place_name(*o.place));
  return fmt::format("{} in flight ({})", action_text(action_of(o.transition, o.action)),
                     cn.net.transition_name(o.transition));
}

std::string ExploredNet::step_label(petri::TransitionId t) const {
  const auto& st = an.steps[t];
  if (st.kind == AnalysisNet::Step::Kind::Transition) return std::string(cn.net.transition_name(st.transition));
  const ActionSpec& a = action_of(st.transition, st.action);
  if (st.kind == AnalysisNet::Step::Kind::Forget) {
    return fmt::format("guard {} forgetting {} ({})", cn.guards[st.answer].name, action_text(a),
                       cn.net.transition_name(st.transition));
  }
  return fmt::format("{} answering {}", action_text(a), answer_text(program, a, st.answer));
}

}  // namespace strata::coral::detail

namespace strata::coral {

TraceStep trace_step(const Program& program, const AnalysisNet& an, petri::TransitionId t) {
  const CompiledNet& cn = *an.source;
  const auto& st = an.steps[t];
  TraceStep step;
  step.transition = cn.net.transition_name(st.transition);
  if (st.kind == AnalysisNet::Step::Kind::Forget) {
    // The engine does this itself when the guard trips: shown as a firing
    // of the analysis net's drop, which issues and marks nothing.
    step.kind = TraceStep::Kind::Fire;
    step.transition = an.net.transition_name(t);
    return step;
  }
  if (st.kind == AnalysisNet::Step::Kind::Transition) {
    step.kind = TraceStep::Kind::Fire;
    for (const auto& a : cn.actions[st.transition]) step.actions.push_back(action_text(a));
    for (const petri::Arc& a : cn.net.outputs(st.transition)) step.marks.emplace_back(cn.net.place_name(a.node));
    return step;
  }
  const ActionSpec& a = cn.actions[st.transition][st.action];
  step.kind = TraceStep::Kind::Answer;
  step.action = action_text(a);
  step.answer = answer_text(program, a, st.answer);
  step.primitive = a.target;
  if (a.kind == ActionSpec::Kind::Phase) {
    step.tactic = "phase";
  } else {
    for (char c : tactic_type_name(a.tactic))
      step.tactic += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  step.marks.emplace_back(cn.net.place_name(a.outcomes.at(st.answer)));
  return step;
}

}  // namespace strata::coral

namespace strata::coral::detail {

Counterexample ExploredNet::trace_to(StateId s) const { return trace_along(graph.path_to(s), s); }

// The steps of `path` from the initial marking, which end at state `s`.
Counterexample ExploredNet::trace_along(const std::vector<petri::TransitionId>& path, StateId s) const {
  Counterexample cx;
  for (petri::TransitionId t : path) cx.steps.push_back(trace_step(program, an, t));
  auto m = graph.marking(s);
  std::vector<std::string> marked;
  for (petri::PlaceId p = 0; p < m.size(); ++p) {
    if (m[p] == 0) continue;
    const auto& o = an.places[p];
    if (o.place) {
      marked.push_back(fmt::format("{}:{}", cn.net.place_name(*o.place), m[p]));
    } else {
      std::string what =
          fmt::format("{} ({})", action_text(action_of(o.transition, o.action)), cn.net.transition_name(o.transition));
      cx.in_flight.push_back(m[p] == 1 ? what : fmt::format("{} x{}", what, m[p]));
    }
  }
  cx.marking = marked.empty() ? "(empty)" : join(marked, " ");
  return cx;
}

}  // namespace strata::coral::detail
