#include "coral/verifier.h"

#include <algorithm>
#include <deque>
#include <functional>
#include <set>

#include <fmt/format.h>

#include "coral/analysis.h"
#include "petri/invariants.h"
#include "petri/reach_graph.h"

namespace strata::coral {
namespace {

using petri::StateId;
using Status = Property::Status;

std::string join(const std::vector<std::string>& items, std::string_view sep = ", ") {
  std::string s;
  for (const auto& i : items) s += (s.empty() ? "" : std::string(sep)) + i;
  return s;
}

Property named(std::string key) {
  Property p;
  p.key = std::move(key);
  return p;
}

class NetVerifier {
 public:
  NetVerifier(const Program& program, const CompiledNet& cn, const std::vector<PhaseExits>& known,
              const VerifyOptions& options)
      : program_(program), cn_(cn), an_(build_analysis_net(program, cn, known)) {
    petri::ReachOptions ro;
    ro.terminal_places = cn.exits;
    ro.max_states = options.max_states;
    g_ = petri::build_reach_graph(an_.net, ro);
  }

  NetVerification run() {
    NetVerification v;
    v.name = cn_.name;
    v.kind = cn_.kind == ast::Net::Kind::Mission ? "mission" : "phase";
    v.file = cn_.source_file;
    v.places = cn_.net.place_count();
    v.transitions = cn_.net.transition_count();
    v.in_flight_places = an_.net.place_count() - v.places;
    v.outcomes = an_.net.transition_count() - v.transitions;
    v.states = g_.state_count();
    v.edges = g_.edge_count();
    v.complete = g_.complete();
    v.stopped_why = g_.stopped_why();

    bounds_.assign(an_.net.place_count(), 0);
    for (StateId s = 0; s < g_.state_count(); ++s) {
      auto m = g_.marking(s);
      for (std::size_t p = 0; p < m.size(); ++p) bounds_[p] = std::max<std::uint64_t>(bounds_[p], m[p]);
    }
    for (petri::PlaceId p = 0; p < an_.net.place_count(); ++p) {
      v.bounds.push_back({std::string(an_.net.place_name(p)), bounds_[p], !an_.places[p].place.has_value()});
    }
    for (std::size_t e = 0; e < cn_.exits.size(); ++e) {
      v.exits.emplace_back(cn_.net.place_name(cn_.exits[e]));
      v.exit_reachable.push_back(bounds_[cn_.exits[e]] > 0);
    }

    v.properties.push_back(bounded());
    v.properties.push_back(one_safe());
    v.properties.push_back(no_dead());
    v.properties.push_back(no_deadlock());
    v.properties.push_back(can_always_end());
    v.properties.push_back(no_busy_cycle());
    v.properties.push_back(exits_exclusive());

    petri::Semiflows flows = petri::p_semiflows(an_.net);
    v.invariants_complete = flows.complete;
    for (const auto& f : flows.flows) {
      Invariant inv;
      inv.constant = f.constant;
      for (auto [p, w] : f.weights) inv.weights.emplace_back(std::string(an_.net.place_name(p)), w);
      v.invariants.push_back(std::move(inv));
    }
    if (flows.complete) {
      for (petri::PlaceId p = 0; p < an_.net.place_count(); ++p) {
        if (!flows.covered[p]) v.uncovered.emplace_back(an_.net.place_name(p));
      }
    }
    return v;
  }

 private:
  // ---- properties -----------------------------------------------------------
  Property bounded() const {
    Property p = named("bounded");
    if (const auto& u = g_.unbounded()) {
      std::vector<std::string> grows;
      auto m = g_.marking(u->state), a = g_.marking(u->ancestor);
      for (std::size_t i = 0; i < m.size(); ++i) {
        if (m[i] > a[i]) grows.push_back(place_label(static_cast<petri::PlaceId>(i)));
      }
      p.status = Status::Fails;
      p.message = fmt::format("unbounded: {} can grow without limit; the steps from step {} on can repeat for ever",
                              join(grows), g_.path_to(u->ancestor).size() + 1);
      p.counterexample = trace_to(u->state);
      p.counterexample->repeat_from = g_.path_to(u->ancestor).size();
      return p;
    }
    if (!g_.complete()) return undecided(p);
    p.message = fmt::format("every place is bounded (the most tokens in one place: {})", max_bound());
    return p;
  }

  Property one_safe() const {
    Property p = named("one_safe");
    for (StateId s = 0; s < g_.state_count(); ++s) {
      auto m = g_.marking(s);
      for (std::size_t i = 0; i < m.size(); ++i) {
        if (m[i] < 2) continue;
        p.status = Status::Fails;
        p.message = fmt::format("{} can hold {} tokens", place_label(static_cast<petri::PlaceId>(i)), m[i]);
        p.counterexample = trace_to(s);
        return p;
      }
    }
    if (g_.unbounded()) {
      p.status = Status::Fails;
      p.message = "an unbounded place holds 2 tokens and more (see bounded)";
      return p;
    }
    if (!g_.complete()) return undecided(p);
    p.message = "no place holds more than 1 token";
    return p;
  }

  Property no_dead() const {
    Property p = named("no_dead");
    std::vector<bool> fired(an_.net.transition_count(), false);
    for (StateId s = 0; s < g_.state_count(); ++s) {
      for (const auto& e : g_.successors(s)) fired[e.transition] = true;
    }
    std::vector<std::string> dead;
    for (petri::TransitionId t = 0; t < cn_.net.transition_count(); ++t) {
      if (fired[t]) continue;
      std::string why;
      for (const petri::Arc& a : cn_.net.inputs(t)) {
        if (bounds_[a.node] < a.weight) {
          why = a.weight == 1 ? fmt::format(" ({} is never marked)", cn_.net.place_name(a.node))
                              : fmt::format(" ({} never holds {} tokens)", cn_.net.place_name(a.node), a.weight);
          break;
        }
      }
      dead.push_back(fmt::format("{}{}", cn_.net.transition_name(t), why));
    }
    if (dead.empty()) {
      p.message = cn_.net.transition_count() == 1 ? "the one transition can fire"
                                                   : fmt::format("each of the {} transitions can fire", cn_.net.transition_count());
      return p;
    }
    if (!g_.complete()) return undecided(p);
    p.status = Status::Fails;
    p.message = fmt::format("never fire{}: {}", dead.size() == 1 ? "s" : "", join(dead));
    return p;
  }

  Property no_deadlock() const {
    Property p = named("no_deadlock");
    if (ends_when_dead()) {
      p.message = "a mission net without exits ends when nothing is enabled and nothing is in flight";
      return p;
    }
    for (StateId s = 0; s < g_.state_count(); ++s) {
      if (!g_.explored(s) || g_.terminal(s) || !g_.successors(s).empty()) continue;
      p.status = Status::Fails;
      p.counterexample = trace_to(s);
      p.message = p.counterexample->in_flight.empty()
                      ? "deadlock: nothing enabled, nothing in flight and no exit marked (the engine reports a stall)"
                      : "deadlock: nothing enabled, and what is in flight can never end (its phase reaches no exit)";
      return p;
    }
    if (!g_.complete()) return undecided(p);
    p.message = "every run that stops, stops at an exit";
    return p;
  }

  Property can_always_end() const {
    Property p = named("can_always_end");
    if (!g_.complete()) return undecided(p);
    const std::size_t n = g_.state_count();
    // Backwards from the ends: markings with an exit, or, for a mission net
    // without exits, dead ones. (A phase without exits has no end.)
    std::vector<bool> ends(n, false);
    std::deque<StateId> queue;
    for (StateId s = 0; s < n; ++s) {
      const bool end = ends_when_dead() ? g_.successors(s).empty() : g_.terminal(s);
      if (end) {
        ends[s] = true;
        queue.push_back(s);
      }
    }
    while (!queue.empty()) {
      StateId s = queue.front();
      queue.pop_front();
      for (const auto& e : predecessors(s)) {
        if (!ends[e.target]) {
          ends[e.target] = true;
          queue.push_back(e.target);
        }
      }
    }
    // The nearest marking (breadth-first order) that cannot end.
    StateId bad = 0;
    while (bad < n && ends[bad]) ++bad;
    const std::string goal = ends_when_dead() ? "the end (nothing enabled)" : "an exit";
    if (bad == n) {
      p.message = fmt::format("{} stays reachable from every marking", goal);
      return p;
    }
    p.status = Status::Fails;
    if (cn_.exits.empty() && !ends_when_dead()) {
      p.message = "a phase without exits can never end";
    } else if (g_.successors(bad).empty()) {
      p.message = fmt::format("trapped: {} can no longer be reached (nothing can fire)", goal);
    } else {
      p.message = fmt::format("trapped: from here {} can no longer be reached; only {} can still happen", goal,
                              join(labels(reachable_steps(bad))));
    }
    p.counterexample = trace_to(bad);
    return p;
  }

  // A cycle of firings that issue nothing to wait for: the engine, which
  // fires until nothing is enabled, may go round it for ever.
  Property no_busy_cycle() const {
    Property p = named("no_busy_cycle");
    const std::size_t n = g_.state_count();
    auto is_firing = [&](petri::TransitionId t) { return an_.steps[t].kind == AnalysisNet::Step::Kind::Transition; };
    // Peel off markings from which every sequence of firings stops; what
    // remains lies on, or leads into, a cycle of firings alone.
    std::vector<std::uint32_t> firing_out(n, 0);
    std::deque<StateId> queue;
    for (StateId s = 0; s < n; ++s) {
      for (const auto& e : g_.successors(s)) firing_out[s] += is_firing(e.transition) ? 1 : 0;
      if (firing_out[s] == 0) queue.push_back(s);
    }
    while (!queue.empty()) {
      StateId s = queue.front();
      queue.pop_front();
      for (const auto& e : predecessors(s)) {
        if (is_firing(e.transition) && --firing_out[e.target] == 0) queue.push_back(e.target);
      }
    }
    StateId start = 0;
    while (start < n && firing_out[start] == 0) ++start;
    if (start == n) {
      if (!g_.complete()) return undecided(p);
      p.message = "no cycle of firings goes round without waiting for the vehicle";
      return p;
    }
    // A lasso: from the nearest such marking, follow firings that stay in
    // what remains until a marking repeats.
    std::vector<petri::TransitionId> path = g_.path_to(start);
    std::vector<StateId> walk{start};
    std::set<std::string> cycle;
    std::size_t repeat_from = 0;
    for (StateId at = start;;) {
      for (const auto& e : g_.successors(at)) {
        if (!is_firing(e.transition) || firing_out[e.target] == 0) continue;
        path.push_back(e.transition);
        at = e.target;
        break;
      }
      auto seen = std::find(walk.begin(), walk.end(), at);
      if (seen != walk.end()) {
        repeat_from = g_.path_to(start).size() + static_cast<std::size_t>(seen - walk.begin());
        break;
      }
      walk.push_back(at);
    }
    for (std::size_t i = repeat_from; i < path.size(); ++i) cycle.insert(step_label(path[i]));
    p.status = Status::Fails;
    p.message = fmt::format(
        "busy cycle: {} can fire for ever without waiting for the vehicle, from step {} on (the engine stops such "
        "a mission after its firing limit)",
        join({cycle.begin(), cycle.end()}), repeat_from + 1);
    p.counterexample = trace_along(path, walk.back());
    p.counterexample->repeat_from = repeat_from;
    return p;
  }

  Property exits_exclusive() const {
    Property p = named("exits_exclusive");
    if (cn_.exits.size() < 2) {
      p.message = cn_.exits.empty() ? "no exits" : "one exit";
      return p;
    }
    for (StateId s = 0; s < g_.state_count(); ++s) {
      auto m = g_.marking(s);
      std::vector<std::string> marked;
      for (petri::PlaceId e : cn_.exits) {
        if (m[e] > 0) marked.emplace_back(cn_.net.place_name(e));
      }
      if (marked.size() < 2) continue;
      p.status = Status::Fails;
      p.message = fmt::format("exits {} are marked together (the engine takes the first declared)", join(marked));
      p.counterexample = trace_to(s);
      return p;
    }
    if (!g_.complete()) return undecided(p);
    p.message = "no marking holds two exits";
    return p;
  }

  Property undecided(Property p) const {
    p.status = Status::Undecided;
    p.message = fmt::format("not decided: the exploration stopped ({})", g_.stopped_why());
    return p;
  }

  // A mission net without exits ends when nothing is enabled; a phase
  // without exits never ends.
  bool ends_when_dead() const { return cn_.exits.empty() && cn_.kind == ast::Net::Kind::Mission; }

  // Edges into s, with `target` holding their source; built on first use.
  std::span<const petri::ReachEdge> predecessors(StateId s) const {
    if (pred_begin_.empty()) {
      const std::size_t n = g_.state_count();
      pred_begin_.assign(n + 1, 0);
      for (StateId q = 0; q < n; ++q) {
        for (const auto& e : g_.successors(q)) ++pred_begin_[e.target + 1];
      }
      for (std::size_t i = 0; i < n; ++i) pred_begin_[i + 1] += pred_begin_[i];
      preds_.resize(pred_begin_[n]);
      std::vector<std::size_t> at(pred_begin_.begin(), pred_begin_.end() - 1);
      for (StateId q = 0; q < n; ++q) {
        for (const auto& e : g_.successors(q)) preds_[at[e.target]++] = {e.transition, q};
      }
    }
    return {preds_.data() + pred_begin_[s], preds_.data() + pred_begin_[s + 1]};
  }

  // Every step that can still happen from s.
  std::set<petri::TransitionId> reachable_steps(StateId from) const {
    std::set<petri::TransitionId> steps;
    std::vector<bool> seen(g_.state_count(), false);
    std::vector<StateId> stack{from};
    seen[from] = true;
    while (!stack.empty()) {
      StateId s = stack.back();
      stack.pop_back();
      for (const auto& e : g_.successors(s)) {
        steps.insert(e.transition);
        if (!seen[e.target]) {
          seen[e.target] = true;
          stack.push_back(e.target);
        }
      }
    }
    return steps;
  }

  std::vector<std::string> labels(const std::set<petri::TransitionId>& steps) const {
    std::set<std::string> names;
    for (auto t : steps) names.insert(step_label(t));
    return {names.begin(), names.end()};
  }

  // ---- names ----------------------------------------------------------------
  std::uint64_t max_bound() const { return bounds_.empty() ? 0 : *std::max_element(bounds_.begin(), bounds_.end()); }

  const ActionSpec& action_of(petri::TransitionId t, std::size_t i) const { return cn_.actions[t][i]; }

  // A place for people: the mission's name, or the action waiting there.
  std::string place_label(petri::PlaceId p) const {
    const auto& o = an_.places[p];
    if (o.place) return std::string(cn_.net.place_name(*o.place));
    return fmt::format("{} in flight ({})", action_text(action_of(o.transition, o.action)),
                       cn_.net.transition_name(o.transition));
  }

  std::string step_label(petri::TransitionId t) const {
    const auto& st = an_.steps[t];
    if (st.kind == AnalysisNet::Step::Kind::Transition) return std::string(cn_.net.transition_name(st.transition));
    const ActionSpec& a = action_of(st.transition, st.action);
    return fmt::format("{} answering {}", action_text(a), answer_text(program_, a, st.answer));
  }

  Counterexample trace_to(StateId s) const { return trace_along(g_.path_to(s), s); }

  // The steps of `path` from the initial marking, which end at state `s`.
  Counterexample trace_along(const std::vector<petri::TransitionId>& path, StateId s) const {
    Counterexample cx;
    for (petri::TransitionId t : path) {
      const auto& st = an_.steps[t];
      TraceStep step;
      step.transition = cn_.net.transition_name(st.transition);
      if (st.kind == AnalysisNet::Step::Kind::Transition) {
        step.kind = TraceStep::Kind::Fire;
        for (const auto& a : cn_.actions[st.transition]) step.actions.push_back(action_text(a));
        for (const petri::Arc& a : cn_.net.outputs(st.transition)) step.marks.emplace_back(cn_.net.place_name(a.node));
      } else {
        const ActionSpec& a = action_of(st.transition, st.action);
        step.kind = TraceStep::Kind::Answer;
        step.action = action_text(a);
        step.answer = answer_text(program_, a, st.answer);
        step.marks.emplace_back(cn_.net.place_name(a.outcomes.at(st.answer)));
      }
      cx.steps.push_back(std::move(step));
    }
    auto m = g_.marking(s);
    std::vector<std::string> marked;
    for (petri::PlaceId p = 0; p < m.size(); ++p) {
      if (m[p] == 0) continue;
      const auto& o = an_.places[p];
      if (o.place) {
        marked.push_back(fmt::format("{}:{}", cn_.net.place_name(*o.place), m[p]));
      } else {
        std::string what = fmt::format("{} ({})", action_text(action_of(o.transition, o.action)),
                                       cn_.net.transition_name(o.transition));
        cx.in_flight.push_back(m[p] == 1 ? what : fmt::format("{} x{}", what, m[p]));
      }
    }
    cx.marking = marked.empty() ? "(empty)" : join(marked, " ");
    return cx;
  }

  const Program& program_;
  const CompiledNet& cn_;
  AnalysisNet an_;
  petri::ReachGraph g_;
  std::vector<std::uint64_t> bounds_;
  mutable std::vector<std::size_t> pred_begin_;
  mutable std::vector<petri::ReachEdge> preds_;
};

// Nets in an order that puts every phase before the nets that call it (a
// cycle of PHASE calls, which the checker reports, is cut where found).
std::vector<std::size_t> callee_first(const Program& program, bool mission_only) {
  std::vector<int> state(program.nets.size(), 0);  // 0 new, 1 on the path, 2 done
  std::vector<std::size_t> order;
  std::function<void(std::size_t)> visit = [&](std::size_t i) {
    state[i] = 1;
    for (const auto& actions : program.nets[i].actions) {
      for (const auto& a : actions) {
        if (a.kind != ActionSpec::Kind::Phase) continue;
        for (std::size_t j = 0; j < program.nets.size(); ++j) {
          if (program.nets[j].name == a.target && state[j] == 0) visit(j);
        }
      }
    }
    state[i] = 2;
    order.push_back(i);
  };
  if (mission_only && program.mission) {
    visit(*program.mission);
    return order;
  }
  for (std::size_t i = 0; i < program.nets.size(); ++i) {
    if (state[i] == 0) visit(i);
  }
  return order;
}

}  // namespace

bool NetVerification::ok() const {
  return std::all_of(properties.begin(), properties.end(),
                     [](const Property& p) { return p.status == Property::Status::Holds; });
}

bool VerifyReport::ok() const {
  return std::all_of(nets.begin(), nets.end(), [](const NetVerification& n) { return n.ok(); });
}

VerifyReport verify_program(const Program& program, const VerifyOptions& options) {
  VerifyReport report;
  std::vector<PhaseExits> known;
  for (std::size_t i : callee_first(program, options.mission_only)) {
    const CompiledNet& cn = program.nets[i];
    NetVerification v = NetVerifier(program, cn, known, options).run();
    if (v.complete) known.push_back({cn.name, v.exit_reachable});
    report.nets.push_back(std::move(v));
  }
  return report;
}

std::vector<PhaseExits> reachable_phase_exits(const VerifyReport& report) {
  std::vector<PhaseExits> known;
  for (const auto& n : report.nets) {
    if (n.complete && n.kind == "phase") known.push_back({n.name, n.exit_reachable});
  }
  return known;
}

}  // namespace strata::coral
