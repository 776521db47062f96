// The verifier's properties (docs/verification.md), each decided on one
// explored net; a property that fails carries its counterexample.
#include <algorithm>
#include <deque>
#include <functional>
#include <set>

#include <fmt/format.h>

#include "coral/verifier_internal.h"

namespace strata::coral::detail {
namespace {

using Status = Property::Status;

Property named(std::string key) {
  Property p;
  p.key = std::move(key);
  return p;
}

Property undecided(const ExploredNet& x, Property p) {
  p.status = Status::Undecided;
  p.message = fmt::format("not decided: the exploration stopped ({})", x.graph.stopped_why());
  return p;
}

// A result about a marking points at its first marked mission place (where
// a stalled or trapped run is left), if any.
void about_marking(const ExploredNet& x, StateId s, Property& p) {
  auto m = x.graph.marking(s);
  for (petri::PlaceId q = 0; q < m.size(); ++q) {
    if (m[q] == 0 || !x.an.places[q].place) continue;
    p.about = Property::About::Place;
    p.about_id = q;
    return;
  }
}

}  // namespace

Property bounded(const ExploredNet& x) {
  Property p = named("bounded");
  if (const auto& u = x.graph.unbounded()) {
    std::vector<std::string> grows;
    auto m = x.graph.marking(u->state), a = x.graph.marking(u->ancestor);
    for (std::size_t i = 0; i < m.size(); ++i) {
      if (m[i] <= a[i]) continue;
      if (grows.empty()) {
        p.about = Property::About::Place;
        p.about_id = static_cast<std::uint32_t>(i);
      }
      grows.push_back(x.place_label(static_cast<petri::PlaceId>(i)));
    }
    p.status = Status::Fails;
    p.message = fmt::format("unbounded: {} can grow without limit; the steps from step {} on can repeat for ever",
                            join(grows), x.graph.path_to(u->ancestor).size() + 1);
    p.counterexample = x.trace_to(u->state);
    p.counterexample->repeat_from = x.graph.path_to(u->ancestor).size();
    return p;
  }
  if (!x.graph.complete()) return undecided(x, p);
  p.message = fmt::format("every place is bounded (the most tokens in one place: {})", x.max_bound());
  return p;
}

Property one_safe(const ExploredNet& x) {
  Property p = named("one_safe");
  for (StateId s = 0; s < x.graph.state_count(); ++s) {
    auto m = x.graph.marking(s);
    for (std::size_t i = 0; i < m.size(); ++i) {
      if (m[i] < 2) continue;
      p.status = Status::Fails;
      p.about = Property::About::Place;
      p.about_id = static_cast<std::uint32_t>(i);
      p.message = fmt::format("{} can hold {} tokens", x.place_label(static_cast<petri::PlaceId>(i)), m[i]);
      p.counterexample = x.trace_to(s);
      return p;
    }
  }
  if (x.graph.unbounded()) {
    p.status = Status::Fails;
    p.message = "an unbounded place holds 2 tokens and more (see bounded)";
    return p;
  }
  if (!x.graph.complete()) return undecided(x, p);
  p.message = "no place holds more than 1 token";
  return p;
}

Property no_dead(const ExploredNet& x) {
  Property p = named("no_dead");
  std::vector<bool> fired(x.an.net.transition_count(), false);
  for (StateId s = 0; s < x.graph.state_count(); ++s) {
    for (const auto& e : x.graph.successors(s)) fired[e.transition] = true;
  }
  std::vector<std::string> dead;
  std::size_t written = 0;
  for (petri::TransitionId t = 0; t < x.cn.net.transition_count(); ++t) {
    // A guard's nodes are not the mission's design: a drop of a place that
    // is never marked when it trips is fine.
    if (x.cn.generated(t)) continue;
    ++written;
    if (fired[t]) continue;
    if (dead.empty()) {
      p.about = Property::About::Transition;
      p.about_id = t;
    }
    std::string why;
    for (const petri::Arc& a : x.cn.net.inputs(t)) {
      if (x.bounds[a.node] < a.weight) {
        why = a.weight == 1 ? fmt::format(" ({} is never marked)", x.cn.net.place_name(a.node))
                            : fmt::format(" ({} never holds {} tokens)", x.cn.net.place_name(a.node), a.weight);
        break;
      }
    }
    dead.push_back(fmt::format("{}{}", x.cn.net.transition_name(t), why));
  }
  if (dead.empty()) {
    p.message =
        written == 1 ? "the one transition can fire" : fmt::format("each of the {} transitions can fire", written);
    return p;
  }
  if (!x.graph.complete()) return undecided(x, p);
  p.status = Status::Fails;
  p.message = fmt::format("never fire{}: {}", dead.size() == 1 ? "s" : "", join(dead));
  return p;
}

Property no_deadlock(const ExploredNet& x) {
  Property p = named("no_deadlock");
  if (x.ends_when_dead()) {
    p.message = "a mission net without exits ends when nothing is enabled and nothing is in flight";
    return p;
  }
  for (StateId s = 0; s < x.graph.state_count(); ++s) {
    if (!x.graph.explored(s) || x.graph.terminal(s)) continue;
    // Guards poll for ever: a marking where only their cycles can go on is
    // stopped all the same (the engine reports a stall).
    const auto next = x.graph.successors(s);
    const bool only_guards = !next.empty() && std::all_of(next.begin(), next.end(), [&](const petri::ReachEdge& e) {
      return x.an.guard_cycle(e.transition);
    });
    if (!next.empty() && !only_guards) continue;
    p.status = Status::Fails;
    about_marking(x, s, p);
    p.counterexample = x.trace_to(s);
    p.message = only_guards ? "deadlock: nothing but the guards' polls can go on, and no exit is marked (the engine "
                              "reports a stall)"
                : p.counterexample->in_flight.empty()
                    ? "deadlock: nothing enabled, nothing in flight and no exit marked (the engine reports a stall)"
                    : "deadlock: nothing enabled, and what is in flight can never end (its phase reaches no exit)";
    return p;
  }
  if (!x.graph.complete()) return undecided(x, p);
  p.message = "every run that stops, stops at an exit";
  return p;
}

Property can_always_end(const ExploredNet& x) {
  Property p = named("can_always_end");
  if (!x.graph.complete()) return undecided(x, p);
  const std::size_t n = x.graph.state_count();
  // Backwards from the ends: markings with an exit, or, for a mission net
  // without exits, dead ones. (A phase without exits has no end.)
  std::vector<bool> ends(n, false);
  std::deque<StateId> queue;
  for (StateId s = 0; s < n; ++s) {
    const bool end = x.ends_when_dead() ? x.graph.successors(s).empty() : x.graph.terminal(s);
    if (end) {
      ends[s] = true;
      queue.push_back(s);
    }
  }
  while (!queue.empty()) {
    StateId s = queue.front();
    queue.pop_front();
    for (const auto& e : x.predecessors(s)) {
      // Not by a guard tripping: a mission must end without a fault.
      if (x.an.trips(e.transition)) continue;
      if (!ends[e.target]) {
        ends[e.target] = true;
        queue.push_back(e.target);
      }
    }
  }
  // The nearest marking (breadth-first order) that cannot end.
  StateId bad = 0;
  while (bad < n && ends[bad]) ++bad;
  const std::string goal = std::string(x.ends_when_dead() ? "the end (nothing enabled)" : "an exit") +
                           (x.cn.guards.empty() ? "" : " (without a guard tripping)");
  if (bad == n) {
    p.message = fmt::format("{} stays reachable from every marking", goal);
    return p;
  }
  p.status = Status::Fails;
  if (x.cn.exits.empty() && !x.ends_when_dead()) {
    p.message = "a phase without exits can never end";
  } else if (x.graph.successors(bad).empty()) {
    p.message = fmt::format("trapped: {} can no longer be reached (nothing can fire)", goal);
  } else {
    // What the mission itself can still do: a guard's own steps are not that.
    std::set<petri::TransitionId> steps = x.reachable_steps(bad);
    std::erase_if(
        steps, [&](petri::TransitionId t) { return x.an.guard_cycle(t) || (!x.an.urgent.empty() && x.an.urgent[t]); });
    p.message = steps.empty() ? fmt::format(
                                    "trapped: from here {} can no longer be reached; only the guards can "
                                    "still poll",
                                    goal)
                              : fmt::format("trapped: from here {} can no longer be reached; only {} can still happen",
                                            goal, join(x.labels(steps)));
  }
  about_marking(x, bad, p);
  p.counterexample = x.trace_to(bad);
  return p;
}

// A cycle of firings that issue nothing to wait for: the engine, which
// fires until nothing is enabled, may go round it for ever.
Property no_busy_cycle(const ExploredNet& x) {
  Property p = named("no_busy_cycle");
  const std::size_t n = x.graph.state_count();
  auto is_firing = [&](petri::TransitionId t) { return x.an.steps[t].kind == AnalysisNet::Step::Kind::Transition; };
  // Peel off markings from which every sequence of firings stops; what
  // remains lies on, or leads into, a cycle of firings alone.
  std::vector<std::uint32_t> firing_out(n, 0);
  std::deque<StateId> queue;
  for (StateId s = 0; s < n; ++s) {
    for (const auto& e : x.graph.successors(s)) firing_out[s] += is_firing(e.transition) ? 1 : 0;
    if (firing_out[s] == 0) queue.push_back(s);
  }
  while (!queue.empty()) {
    StateId s = queue.front();
    queue.pop_front();
    for (const auto& e : x.predecessors(s)) {
      if (is_firing(e.transition) && --firing_out[e.target] == 0) queue.push_back(e.target);
    }
  }
  StateId start = 0;
  while (start < n && firing_out[start] == 0) ++start;
  if (start == n) {
    if (!x.graph.complete()) return undecided(x, p);
    p.message = "no cycle of firings goes round without waiting for the vehicle";
    return p;
  }
  // A lasso: from the nearest such marking, follow firings that stay in
  // what remains until a marking repeats.
  std::vector<petri::TransitionId> path = x.graph.path_to(start);
  std::vector<StateId> walk{start};
  std::set<std::string> cycle;
  std::size_t repeat_from = 0;
  for (StateId at = start;;) {
    for (const auto& e : x.graph.successors(at)) {
      if (!is_firing(e.transition) || firing_out[e.target] == 0) continue;
      path.push_back(e.transition);
      at = e.target;
      break;
    }
    auto seen = std::find(walk.begin(), walk.end(), at);
    if (seen != walk.end()) {
      repeat_from = x.graph.path_to(start).size() + static_cast<std::size_t>(seen - walk.begin());
      break;
    }
    walk.push_back(at);
  }
  for (std::size_t i = repeat_from; i < path.size(); ++i) cycle.insert(x.step_label(path[i]));
  if (repeat_from < path.size()) {
    p.about = Property::About::Transition;
    p.about_id = x.an.steps[path[repeat_from]].transition;
  }
  p.status = Status::Fails;
  p.message = fmt::format(
      "busy cycle: {} can fire for ever without waiting for the vehicle, from step {} on (the engine stops such "
      "a mission after its firing limit)",
      join({cycle.begin(), cycle.end()}), repeat_from + 1);
  p.counterexample = x.trace_along(path, walk.back());
  p.counterexample->repeat_from = repeat_from;
  return p;
}

Property exits_exclusive(const ExploredNet& x) {
  Property p = named("exits_exclusive");
  if (x.cn.exits.size() < 2) {
    p.message = x.cn.exits.empty() ? "no exits" : "one exit";
    return p;
  }
  for (StateId s = 0; s < x.graph.state_count(); ++s) {
    auto m = x.graph.marking(s);
    std::vector<std::string> marked;
    for (petri::PlaceId e : x.cn.exits) {
      if (m[e] > 0) marked.emplace_back(x.cn.net.place_name(e));
    }
    if (marked.size() < 2) continue;
    p.status = Status::Fails;
    p.about = Property::About::Place;
    for (petri::PlaceId e : x.cn.exits) {
      if (m[e] > 0) {
        p.about_id = e;  // the first exit marked (mission places keep their ids in the analysis net)
        break;
      }
    }
    p.message = fmt::format("exits {} are marked together (the engine takes the first declared)", join(marked));
    p.counterexample = x.trace_to(s);
    return p;
  }
  if (!x.graph.complete()) return undecided(x, p);
  p.message = "no marking holds two exits";
  return p;
}

namespace {

// States from which some edge of `goal` can be taken, or (goal empty) an
// end reached: backwards over every edge.
std::vector<bool> can_reach(const ExploredNet& x, const std::function<bool(StateId)>& target) {
  const std::size_t n = x.graph.state_count();
  std::vector<bool> reach(n, false);
  std::deque<StateId> queue;
  for (StateId s = 0; s < n; ++s) {
    if (target(s)) {
      reach[s] = true;
      queue.push_back(s);
    }
  }
  while (!queue.empty()) {
    StateId s = queue.front();
    queue.pop_front();
    for (const auto& e : x.predecessors(s)) {
      if (!reach[e.target]) {
        reach[e.target] = true;
        queue.push_back(e.target);
      }
    }
  }
  return reach;
}

// A guard of the net is tripping in s (the first to trip wins: the others
// are stopped then, not blocked).
bool tripping(const ExploredNet& x, StateId s) {
  auto m = x.graph.marking(s);
  return std::any_of(x.cn.guards.begin(), x.cn.guards.end(),
                     [&](const CompiledGuard& g) { return m[g.loop.back()] > 0 || m[g.cancel] > 0; });
}

// Guard g is active in s: its cycle holds a token, a place or a call in flight.
bool active(const ExploredNet& x, std::uint32_t g, StateId s) {
  auto m = x.graph.marking(s);
  const CompiledGuard& guard = x.cn.guards[g];
  for (petri::PlaceId p : guard.loop) {
    if (m[p] > 0) return true;
  }
  for (petri::PlaceId p = 0; p < m.size(); ++p) {
    const auto& o = x.an.places[p];
    if (m[p] == 0 || o.place) continue;
    const GuardNode node = x.cn.guard_node(o.transition);
    if (node.guard == g && (node.role == GuardRole::Poll || node.role == GuardRole::Ask)) return true;
  }
  return false;
}

}  // namespace

Property guards_can_trip(const ExploredNet& x) {
  Property p = named("guards_can_trip");
  if (!x.graph.complete()) return undecided(x, p);
  // After a trip the guards are stopped, on purpose: what follows a trip
  // (forwards from its targets) is not asked of them.
  std::vector<bool> after_trip(x.graph.state_count(), false);
  std::vector<StateId> work;
  for (StateId s = 0; s < x.graph.state_count(); ++s) {
    for (const auto& e : x.graph.successors(s)) {
      const GuardNode node = x.cn.guard_node(x.an.steps[e.transition].transition);
      if (x.an.steps[e.transition].kind == AnalysisNet::Step::Kind::Transition && node.role == GuardRole::Trip &&
          !after_trip[e.target]) {
        after_trip[e.target] = true;
        work.push_back(e.target);
      }
    }
  }
  while (!work.empty()) {
    StateId s = work.back();
    work.pop_back();
    for (const auto& e : x.graph.successors(s)) {
      if (!after_trip[e.target]) {
        after_trip[e.target] = true;
        work.push_back(e.target);
      }
    }
  }
  std::vector<std::string> names;
  for (std::uint32_t g = 0; g < x.cn.guards.size(); ++g) {
    const CompiledGuard& guard = x.cn.guards[g];
    names.push_back(guard.name);
    const std::vector<bool> trips = can_reach(x, [&](StateId s) {
      const auto next = x.graph.successors(s);
      return std::any_of(next.begin(), next.end(),
                         [&](const petri::ReachEdge& e) { return e.transition == guard.trip; });
    });
    for (StateId s = 0; s < x.graph.state_count(); ++s) {
      if (trips[s] || x.graph.terminal(s) || after_trip[s] || tripping(x, s)) continue;
      p.status = Status::Fails;
      p.about = Property::About::Transition;
      p.about_id = guard.trip;
      p.message =
          active(x, g, s)
              ? fmt::format("guard {} is blocked: it is polling here but can never trip from here on", guard.name)
              : fmt::format("guard {} has stopped polling here, though no guard tripped", guard.name);
      p.counterexample = x.trace_to(s);
      return p;
    }
  }
  p.message = fmt::format("{} can trip from every marking where it is polling",
                          names.size() == 1 ? "the guard " + names[0] : "every guard (" + join(names) + ")");
  return p;
}

Property guard_handlers_end(const ExploredNet& x) {
  Property p = named("handlers_end");
  if (!x.graph.complete()) return undecided(x, p);
  const std::vector<bool> ends =
      can_reach(x, [&](StateId s) { return x.ends_when_dead() ? x.graph.successors(s).empty() : x.graph.terminal(s); });
  std::vector<std::string> found;
  for (const CompiledGuard& guard : x.cn.guards) {
    std::set<StateId> after;
    for (StateId s = 0; s < x.graph.state_count(); ++s) {
      for (const auto& e : x.graph.successors(s)) {
        if (e.transition == guard.trip) after.insert(e.target);
      }
    }
    for (StateId s : after) {
      if (ends[s]) continue;
      p.status = Status::Fails;
      p.about = Property::About::Transition;
      p.about_id = guard.handle;
      p.message = fmt::format("after guard {} trips, its handler can end up where no exit is reachable", guard.name);
      p.counterexample = x.trace_to(s);
      return p;
    }
    // The exits its handler can reach, for people.
    std::set<std::string> exits;
    std::vector<bool> seen(x.graph.state_count(), false);
    std::vector<StateId> stack(after.begin(), after.end());
    for (StateId s : stack) seen[s] = true;
    while (!stack.empty()) {
      StateId s = stack.back();
      stack.pop_back();
      auto m = x.graph.marking(s);
      for (petri::PlaceId e : x.cn.exits) {
        if (m[e] > 0) exits.insert(std::string(x.cn.net.place_name(e)));
      }
      for (const auto& e : x.graph.successors(s)) {
        if (!seen[e.target]) {
          seen[e.target] = true;
          stack.push_back(e.target);
        }
      }
    }
    found.push_back(after.empty() ? fmt::format("{}: never trips", guard.name)
                                  : fmt::format("{} -> {}", guard.name,
                                                exits.empty() ? std::string("the end")
                                                              : join({exits.begin(), exits.end()}, " or ")));
  }
  p.message = fmt::format("every trip's handler reaches an exit ({})", join(found, "; "));
  return p;
}

}  // namespace strata::coral::detail

namespace strata::coral::detail {

Property phase_depth(const Program& program, const CompiledNet& cn) {
  Property p = named("phase_depth");
  // below[i]: how many PHASE calls deep net i goes; next[i]: the net its
  // deepest call runs. Iterative (a chain of phases may be long); a cycle,
  // which the checker reports, counts as past the limit.
  constexpr std::size_t kUnknown = static_cast<std::size_t>(-1), kCycle = static_cast<std::size_t>(-2);
  const std::size_t n = program.nets.size();
  std::vector<std::size_t> below(n, kUnknown), next(n, kUnknown);
  std::vector<bool> on_path(n, false);
  auto index_of = [&](const CompiledNet* net) { return static_cast<std::size_t>(net - program.nets.data()); };
  auto callees = [&](std::size_t i) {
    std::vector<std::size_t> out;
    for (const auto& actions : program.nets[i].actions) {
      for (const auto& a : actions) {
        if (a.kind != ActionSpec::Kind::Phase) continue;
        if (const CompiledNet* target = program.find(a.target)) out.push_back(index_of(target));
      }
    }
    return out;
  };
  const std::size_t root = index_of(&cn);
  std::vector<std::pair<std::size_t, std::vector<std::size_t>>> stack;
  stack.emplace_back(root, callees(root));
  on_path[root] = true;
  below[root] = 0;
  while (!stack.empty()) {
    auto& [i, todo] = stack.back();
    if (todo.empty()) {
      on_path[i] = false;
      const std::size_t done = i;
      stack.pop_back();
      if (!stack.empty()) {
        const std::size_t caller = stack.back().first;
        const std::size_t d = below[done] == kCycle ? kCycle : below[done] + 1;
        if (below[caller] != kCycle && (d == kCycle || d > below[caller])) {
          below[caller] = d;
          next[caller] = done;
        }
      }
      continue;
    }
    const std::size_t j = todo.back();
    todo.pop_back();
    if (on_path[j]) {
      below[i] = kCycle;
      next[i] = j;
      continue;
    }
    if (below[j] != kUnknown) {
      const std::size_t d = below[j] == kCycle ? kCycle : below[j] + 1;
      if (below[i] != kCycle && (d == kCycle || d > below[i])) {
        below[i] = d;
        next[i] = j;
      }
      continue;
    }
    below[j] = 0;
    on_path[j] = true;
    std::vector<std::size_t> c = callees(j);
    stack.emplace_back(j, std::move(c));
  }
  const std::size_t start = cn.kind == ast::Net::Kind::Mission ? 0 : 1;
  const bool cycle = below[root] == kCycle;
  const std::size_t deepest = cycle ? kCycle : start + below[root];
  if (!cycle && deepest <= kMaxPhaseDepth) {
    p.message = below[root] == 0
                    ? fmt::format("calls no phase (the engine's limit: {} deep)", kMaxPhaseDepth)
                    : fmt::format("phases nest at most {} deep (the engine's limit: {})", deepest, kMaxPhaseDepth);
    return p;
  }
  // The chain of calls, shortened in the middle.
  std::vector<std::string> chain;
  std::size_t at = root;
  for (std::size_t k = 0; k <= n && at != kUnknown; ++k, at = next[at]) {
    chain.push_back(program.nets[at].name);
    if (below[at] == 0) break;
  }
  if (chain.size() > 8) {
    const std::size_t total = chain.size();
    chain.erase(chain.begin() + 4, chain.end() - 3);
    chain.insert(chain.begin() + 4, fmt::format("... {} more ...", total - 7));
  }
  p.status = Status::Fails;
  p.message = cycle ? fmt::format("a cycle of PHASE calls nests without end ({})", join(chain, " -> "))
                    : fmt::format("would nest phases {} deep, past the engine's limit of {} ({})", deepest,
                                  kMaxPhaseDepth, join(chain, " -> "));
  return p;
}

}  // namespace strata::coral::detail
