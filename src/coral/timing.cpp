// The timing analysis's answer (coral/timing.h): the worst and best cases
// read from the graph of timed states (timing_explore.cpp), with their paths.
#include "coral/timing.h"

#include <algorithm>
#include <deque>
#include <limits>
#include <unordered_map>

#include <fmt/format.h>

#include "coral/timing_internal.h"
#include "coral/verifier.h"

namespace strata::coral {
namespace timing_detail {
namespace {

// ------------------------------------------------------------------ the answer

class Solver {
 public:
  Solver(const TimedGraph& x, const Model& m, const Program& p, const BoundQuery& q, const BoundOptions& o)
      : x_(x), m_(m), program_(p), q_(q), o_(o) {}

  BoundAnswer solve() {
    BoundAnswer a;
    a.states = x_.keys_.size();
    std::vector<std::uint32_t> starts = x_.start_ids_;
    std::sort(starts.begin(), starts.end());
    starts.erase(std::unique(starts.begin(), starts.end()), starts.end());
    if (starts.empty() && !x_.immediate_) {
      a.verdict = BoundAnswer::Verdict::NoEvent;
      a.message = "the event happens in no run";
      return a;
    }
    sccs();
    const std::size_t n = comp_count_;
    // By component, sinks first: the longest time to TO (-1: none), whether
    // time can pass for ever, whether a run can end without TO.
    worst_.assign(n, -1);
    std::vector<std::uint8_t> unbounded(n, 0), ends(n, 0);
    cyclic_.assign(n, 0);
    for (std::uint32_t c = 0; c < n; ++c) {
      for (std::uint32_t u : members_[c]) {
        const std::uint32_t e0 = x_.first_edge_[u], e1 = x_.first_edge_[u + 1];
        if (e0 == e1) ends[c] = 1;  // the run ends here (an exit, or stuck)
        for (std::uint32_t e = e0; e < e1; ++e) {
          const Edge& ed = x_.edges_[e];
          if (ed.to == kTo) {
            worst_[c] = std::max<std::int64_t>(worst_[c], ed.w);
            continue;
          }
          const std::uint32_t d = comp_[ed.to];
          if (d == c) {
            if (ed.w > 0) cyclic_[c] = unbounded[c] = 1;
            continue;
          }
          unbounded[c] |= unbounded[d];
          ends[c] |= ends[d];
          if (worst_[d] >= 0) worst_[c] = std::max<std::int64_t>(worst_[c], ed.w + worst_[d]);
        }
      }
    }
    const double tick = o_.tick_s;
    const double extra = q_.to == BoundQuery::To::Surface ? o_.ascent_s : 0.0;
    for (std::uint32_t s : starts) {
      if (!ends[comp_[s]] || a.ends_without) continue;
      a.ends_without = true;
      a.ends_without_path = prefix(s);
      auto way = bfs(s, [&](std::uint32_t v) { return x_.first_edge_[v] == x_.first_edge_[v + 1]; });
      render(way, a.ends_without_path);
    }
    // Unbounded first: it is the answer whatever the rest says.
    for (std::uint32_t s : starts) {
      if (!unbounded[comp_[s]]) continue;
      a.verdict = BoundAnswer::Verdict::Unbounded;
      a.message = "TO can be put off for ever: a cycle that lets time pass repeats without it";
      a.path = prefix(s);
      // To a state of a cycle that lets time pass, then round it.
      auto way = bfs(s, [&](std::uint32_t v) { return cyclic_[comp_[v]] != 0; });
      const std::int64_t at = render(way, a.path);
      const std::uint32_t u = way.empty() ? s : x_.edges_[way.back()].to;
      std::uint32_t positive = kTo;
      std::uint32_t source = kTo;
      for (std::uint32_t v : members_[comp_[u]]) {
        for (std::uint32_t e = x_.first_edge_[v]; e < x_.first_edge_[v + 1] && positive == kTo; ++e) {
          const Edge& ed = x_.edges_[e];
          if (ed.to != kTo && ed.w > 0 && comp_[ed.to] == comp_[u]) {
            positive = e;
            source = v;
          }
        }
        if (positive != kTo) break;
      }
      std::vector<std::uint32_t> loop = bfs(
          u, [&](std::uint32_t v) { return v == source; }, comp_[u]);
      const std::int64_t before = render(loop, a.path, at);
      std::vector<std::uint32_t> round{positive};
      auto back = bfs(
          x_.edges_[positive].to, [&](std::uint32_t v) { return v == source; }, comp_[u]);
      round.insert(round.end(), back.begin(), back.end());
      render(round, a.cycle, before);
      return a;
    }
    a.verdict = BoundAnswer::Verdict::Bounded;
    std::int64_t top = x_.immediate_ ? 0 : -1;
    std::uint32_t argmax = kTo;
    for (std::uint32_t s : starts) {
      if (worst_[comp_[s]] > top) {
        top = worst_[comp_[s]];
        argmax = s;
      }
    }
    if (top < 0) {
      a.verdict = BoundAnswer::Verdict::Unbounded;
      a.message = "no run reaches TO after the event";
      return a;
    }
    a.worst_s = static_cast<double>(top) * tick + extra;
    a.best_s = static_cast<double>(shortest(starts)) * tick + extra;
    if (argmax != kTo) {
      a.path = prefix(argmax);
      render(worst_way(argmax), a.path);
    } else {
      a.path = prefix_of(x_.immediate_from_.first);
      a.path.push_back(step(x_.immediate_from_.second, 0.0));
    }
    if (extra > 0) {
      a.path.push_back(pass_step(a.worst_s, "", fmt::format("at the surface (the ascent, at most {:.1f} s)", extra)));
    }
    return a;
  }

 private:
  // Iterative Tarjan over every state; components numbered sinks first.
  void sccs() {
    const auto n = static_cast<std::uint32_t>(x_.keys_.size());
    comp_.assign(n, kTo);
    std::vector<std::uint32_t> index(n, kTo), low(n, 0), stack;
    std::vector<std::uint8_t> on(n, 0);
    std::vector<std::pair<std::uint32_t, std::uint32_t>> call;  // (state, next edge)
    std::uint32_t counter = 0;
    for (std::uint32_t root = 0; root < n; ++root) {
      if (index[root] != kTo) continue;
      call.emplace_back(root, x_.first_edge_[root]);
      index[root] = low[root] = counter++;
      stack.push_back(root);
      on[root] = 1;
      while (!call.empty()) {
        const std::uint32_t u = call.back().first;
        std::uint32_t& e = call.back().second;
        if (e < x_.first_edge_[u + 1]) {
          const std::uint32_t v = x_.edges_[e++].to;
          if (v == kTo) continue;
          if (index[v] == kTo) {
            index[v] = low[v] = counter++;
            stack.push_back(v);
            on[v] = 1;
            call.emplace_back(v, x_.first_edge_[v]);
          } else if (on[v]) {
            low[u] = std::min(low[u], index[v]);
          }
          continue;
        }
        call.pop_back();
        if (!call.empty()) low[call.back().first] = std::min(low[call.back().first], low[u]);
        if (low[u] == index[u]) {
          members_.emplace_back();
          std::uint32_t w = 0;
          do {
            w = stack.back();
            stack.pop_back();
            on[w] = 0;
            comp_[w] = comp_count_;
            members_.back().push_back(w);
          } while (w != u);
          ++comp_count_;
        }
      }
    }
  }

  // 0-1 BFS from the start states to the first TO.
  std::int64_t shortest(const std::vector<std::uint32_t>& starts) const {
    std::vector<std::int64_t> dist(x_.keys_.size(), std::numeric_limits<std::int64_t>::max());
    std::deque<std::uint32_t> q;
    for (std::uint32_t s : starts) {
      dist[s] = 0;
      q.push_back(s);
    }
    std::int64_t best = x_.immediate_ ? 0 : std::numeric_limits<std::int64_t>::max();
    while (!q.empty()) {
      const std::uint32_t u = q.front();
      q.pop_front();
      for (std::uint32_t e = x_.first_edge_[u]; e < x_.first_edge_[u + 1]; ++e) {
        const Edge& ed = x_.edges_[e];
        const std::int64_t d = dist[u] + ed.w;
        if (ed.to == kTo) {
          best = std::min(best, d);
          continue;
        }
        if (d >= dist[ed.to]) continue;
        dist[ed.to] = d;
        if (ed.w == 0) {
          q.push_front(ed.to);
        } else {
          q.push_back(ed.to);
        }
      }
    }
    return best == std::numeric_limits<std::int64_t>::max() ? 0 : best;
  }

  // The edges of a shortest way (in steps) from s to a state where goal
  // holds, within component `within` when given; empty when s is one.
  template <typename Goal>
  std::vector<std::uint32_t> bfs(std::uint32_t s, Goal goal, std::optional<std::uint32_t> within = {}) const {
    if (goal(s)) return {};
    std::unordered_map<std::uint32_t, std::uint32_t> via{{s, kTo}};  // state: the edge that reached it
    std::vector<std::uint32_t> source_of;                            // by edge index seen: its source
    std::unordered_map<std::uint32_t, std::uint32_t> from;           // edge: source state
    std::deque<std::uint32_t> q{s};
    while (!q.empty()) {
      const std::uint32_t u = q.front();
      q.pop_front();
      for (std::uint32_t e = x_.first_edge_[u]; e < x_.first_edge_[u + 1]; ++e) {
        const std::uint32_t v = x_.edges_[e].to;
        if (v == kTo || via.count(v) || (within && comp_[v] != *within)) continue;
        via.emplace(v, e);
        from.emplace(e, u);
        if (goal(v)) {
          std::vector<std::uint32_t> out;
          for (std::uint32_t w = v; via[w] != kTo; w = from[via[w]]) out.push_back(via[w]);
          std::reverse(out.begin(), out.end());
          return out;
        }
        q.push_back(v);
      }
    }
    return {};
  }

  // The worst case's edges from start s to TO: down the components, each
  // step the one whose value is the component's.
  std::vector<std::uint32_t> worst_way(std::uint32_t s) const {
    std::vector<std::uint32_t> out;
    std::uint32_t u = s;
    for (std::size_t n = 0; n <= x_.keys_.size(); ++n) {
      const std::uint32_t c = comp_[u];
      const std::int64_t want = worst_[c];
      std::uint32_t chosen = kTo;
      auto achieves = [&](std::uint32_t w) {
        for (std::uint32_t e = x_.first_edge_[w]; e < x_.first_edge_[w + 1]; ++e) {
          const Edge& ed = x_.edges_[e];
          const bool ok = ed.to == kTo
                              ? ed.w == want
                              : comp_[ed.to] != c && worst_[comp_[ed.to]] >= 0 && ed.w + worst_[comp_[ed.to]] == want;
          if (ok) {
            chosen = e;
            return true;
          }
        }
        return false;
      };
      auto inside = bfs(u, achieves, c);
      out.insert(out.end(), inside.begin(), inside.end());
      if (chosen == kTo) return out;
      out.push_back(chosen);
      if (x_.edges_[chosen].to == kTo) return out;
      u = x_.edges_[chosen].to;
    }
    return out;
  }

  // Appends the steps of edges to out, times counted from `elapsed` ticks;
  // returns the ticks at the end. Time passing is one step per stretch.
  std::int64_t render(const std::vector<std::uint32_t>& way, std::vector<BoundStep>& out,
                      std::int64_t elapsed = 0) const {
    const double tick = o_.tick_s;
    std::int64_t waited = 0;
    auto flush = [&] {
      if (waited == 0) return;
      elapsed += waited;
      BoundStep b = pass_step(static_cast<double>(elapsed) * tick, "",
                              fmt::format("{:.1f} s pass", static_cast<double>(waited) * tick));
      b.trace.action = fmt::format("{:.1f} s of waiting", static_cast<double>(waited) * tick);
      out.push_back(std::move(b));
      waited = 0;
    };
    for (std::uint32_t e : way) {
      const Edge& ed = x_.edges_[e];
      if (ed.label == kAdvance) {
        waited += ed.w;
        continue;
      }
      flush();
      out.push_back(step(ed.label, static_cast<double>(elapsed) * tick));
    }
    flush();
    return elapsed;
  }

  static BoundStep pass_step(std::optional<double> t, std::string instance, std::string what) {
    BoundStep b{t, std::move(instance), std::move(what), {}};
    b.trace.kind = TraceStep::Kind::Pass;
    b.trace.action = b.what;
    b.trace.instance = b.net;
    b.trace.t_s = t;
    return b;
  }

  BoundStep step(std::uint32_t label, std::optional<double> t) const {
    if (label == kOnset) {
      return pass_step(
          t, "",
          fmt::format("the fault starts: every ask {} answers {} from now on", q_.from_name, q_.fault_value ? 1 : 0));
    }
    const GlobalTransition& g = m_.transitions[label];
    const Inst& in = m_.insts[g.inst];
    const AnalysisNet::Step& st = in.an.steps[g.t];
    const CompiledNet& cn = *in.cn;
    const std::string name(cn.net.transition_name(st.transition));
    const auto& actions = cn.actions[st.transition];
    BoundStep b{t, in.path, name, trace_step(program_, in.an, g.t)};
    b.trace.instance = in.path;
    b.trace.net = cn.name;
    b.trace.t_s = t;
    switch (st.kind) {
      case AnalysisNet::Step::Kind::Transition: {
        b.what = "fires " + name;
        for (std::size_t i = 0; i < actions.size(); ++i) b.what += (i ? ", " : ": ") + action_text(actions[i]);
        break;
      }
      case AnalysisNet::Step::Kind::Outcome: {
        const ActionSpec& a = actions[st.action];
        const char* verb = a.kind == ActionSpec::Kind::Phase ? "ends at" : "answers";
        b.what = fmt::format("{} {} {}", action_text(a), verb, answer_text(program_, a, st.answer));
        break;
      }
      case AnalysisNet::Step::Kind::Forget:
        b.what = fmt::format("guard {} forgets {}", cn.guards.at(st.answer).name, action_text(actions[st.action]));
        break;
    }
    return b;
  }

  // The BFS tree's steps from the initial state to s (before the event).
  std::vector<BoundStep> prefix_of(std::uint32_t s) const {
    std::vector<BoundStep> out;
    for (std::uint32_t u = s; u != 0 && u < x_.parent_.size(); u = x_.parent_[u]) {
      if (x_.parent_label_[u] != kAdvance) out.push_back(step(x_.parent_label_[u], std::nullopt));
    }
    std::reverse(out.begin(), out.end());
    return out;
  }
  // ... then the event's step, at 0 s.
  std::vector<BoundStep> prefix(std::uint32_t start) const {
    auto [from, label] = x_.starts_[start];
    std::vector<BoundStep> out = prefix_of(from);
    out.push_back(step(label, 0.0));
    return out;
  }

  const TimedGraph& x_;
  const Model& m_;
  const Program& program_;
  const BoundQuery& q_;
  const BoundOptions& o_;
  std::vector<std::uint32_t> comp_;
  std::vector<std::vector<std::uint32_t>> members_;
  std::uint32_t comp_count_ = 0;
  std::vector<std::int64_t> worst_;
  std::vector<std::uint8_t> cyclic_;
};

}  // namespace
}  // namespace timing_detail

BoundAnswer analyse_bound(const Program& program, const BoundQuery& query, const BoundOptions& options) {
  BoundAnswer a;
  if (!program.mission) {
    a.message = "the timing analysis needs a mission";
    return a;
  }
  timing_detail::Model m;
  if (auto e = timing_detail::build_model(program, query, options, m)) {
    a.message = *e;
    return a;
  }
  timing_detail::TimedGraph g;
  if (!timing_detail::explore(m, query, options, g)) {
    a.message = g.error_;
    a.states = g.keys_.size();
    return a;
  }
  return timing_detail::Solver(g, m, program, query, options).solve();
}

}  // namespace strata::coral
