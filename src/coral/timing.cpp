#include "coral/timing.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <deque>
#include <limits>
#include <unordered_map>

#include <fmt/format.h>

#include "coral/analysis.h"

namespace strata::coral {
namespace {

using petri::PlaceId;
using petri::TransitionId;

// ------------------------------------------------------------------ the query

struct Cursor {
  std::string_view text;
  std::size_t pos = 0;
  void skip() {
    while (pos < text.size() && (text[pos] == ' ' || text[pos] == '\t')) ++pos;
  }
  // The next word (letters, digits, '_'), or "" (at the end or another character).
  std::string_view word() {
    skip();
    const std::size_t start = pos;
    while (pos < text.size() && (std::isalnum(static_cast<unsigned char>(text[pos])) != 0 || text[pos] == '_')) ++pos;
    return text.substr(start, pos - start);
  }
  core::Error error(std::size_t at, const std::string& message) const {
    return core::make_error(core::ErrorCode::InvalidInput, fmt::format("column {}: {}", at + 1, message));
  }
};

constexpr std::string_view kForms =
    "write FROM -> TO, FROM one of `fault ASK`, `fault not ASK`, `trip GUARD`, `start PHASE`, TO one of "
    "`exec NAME`, `ask NAME`, `ood NAME`, `call NAME`, `exit NAME`, `surface`, then optionally `within S`";

// ------------------------------------------------------------------ the model

// One net as it runs: the mission, or one PHASE call's phase (parameters bound).
struct Inst {
  const CompiledNet* cn = nullptr;
  AnalysisNet an;
  std::uint32_t place0 = 0;        // the global id of its analysis place 0
  std::uint32_t end_place = 0;     // one past the last global place of it and its calls
  std::uint32_t end_inst = 0;      // one past the last instance of its calls
  std::vector<ast::Literal> args;  // its parameters' values, in order
  std::string path;
  std::vector<int> child;   // by analysis place: the instance its PHASE in flight runs (-1: none)
  std::vector<int> lo, hi;  // by analysis place: a call in flight's answer interval, in ticks (-1: none)
};

// A transition of some instance, and what it means to the question.
struct GlobalTransition {
  std::uint32_t inst = 0;
  TransitionId t = 0;
  bool timed = false;            // an answer to a call in flight
  std::int8_t ask_answer = -1;   // an answer of the fault's ask: 1 or 0; -1 otherwise
  std::uint32_t child_exit = 0;  // a PHASE's end: the child's exit place (global); 0 none
  bool is_to = false;            // issues the TO call
  bool is_event = false;         // a guard trip or phase start that is the event
};

struct Model {
  std::vector<Inst> insts;
  std::vector<GlobalTransition> transitions;
  std::uint32_t places = 0;
  std::vector<std::uint32_t> timed_places;            // global ids of calls in flight with an interval
  std::vector<std::int32_t> lo, hi;                   // by global place
  std::vector<std::int32_t> child;                    // by global place
  std::vector<std::uint32_t> mission_exits;           // global
  std::vector<std::vector<std::uint32_t>> consumers;  // by global place: the transitions it is an input of
  std::optional<std::uint32_t> to_exit;               // To::Exit: the global place
};

std::optional<ast::Literal> resolve(const ast::Literal& l, const Inst& inst) {
  if (l.kind != ast::Literal::Kind::Parameter) return l;
  for (std::size_t i = 0; i < inst.cn->params.size() && i < inst.args.size(); ++i) {
    if (inst.cn->params[i].name.text == l.text) return inst.args[i];
  }
  return std::nullopt;
}

class Builder {
 public:
  Builder(const Program& p, const BoundOptions& o, Model& m) : program_(p), options_(o), m_(m) {}

  std::optional<std::string> add(const CompiledNet& cn, std::vector<ast::Literal> args, std::string path,
                                 std::size_t depth) {
    if (depth > kMaxPhaseDepth) return fmt::format("phases nest deeper than {} at {}", kMaxPhaseDepth, path);
    const std::uint32_t idx = static_cast<std::uint32_t>(m_.insts.size());
    m_.insts.push_back({});
    {
      Inst& inst = m_.insts[idx];
      inst.cn = &cn;
      inst.an = build_analysis_net(program_, cn);
      inst.args = std::move(args);
      inst.path = std::move(path);
      inst.place0 = m_.places;
      const std::size_t n = inst.an.net.place_count();
      inst.child.assign(n, -1);
      inst.lo.assign(n, -1);
      inst.hi.assign(n, -1);
      m_.places += static_cast<std::uint32_t>(n);
    }
    const std::size_t n = m_.insts[idx].an.net.place_count();
    std::unordered_map<std::string, int> calls;
    for (PlaceId pl = 0; pl < n; ++pl) {
      const AnalysisNet::PlaceOrigin origin = m_.insts[idx].an.places[pl];
      if (origin.place) continue;
      const ActionSpec& a = cn.actions[origin.transition][origin.action];
      if (a.kind == ActionSpec::Kind::Phase) {
        const CompiledNet* phase = program_.find(a.target);
        if (!phase) return fmt::format("{}: no phase net {}", m_.insts[idx].path, a.target);
        std::vector<ast::Literal> call_args;
        for (const ast::Literal& l : a.args) {
          auto v = resolve(l, m_.insts[idx]);
          if (!v) return fmt::format("{}: parameter {} has no value", m_.insts[idx].path, l.text);
          call_args.push_back(*v);
        }
        const int k = ++calls[a.target];
        std::string child_path = fmt::format("{}/{}#{}", m_.insts[idx].path, a.target, k);
        const auto child = static_cast<int>(m_.insts.size());
        if (auto e = add(*phase, std::move(call_args), std::move(child_path), depth + 1)) return e;
        m_.insts[idx].child[pl] = child;
        continue;
      }
      auto timing = options_.primitive ? options_.primitive(a.target) : std::nullopt;
      if (!timing) return fmt::format("the catalogue has no primitive {} (called in {})", a.target, cn.name);
      double lo = 0;
      double hi = timing->reply_s;
      if (timing->wait_arg) {
        double wait = timing->wait_arg_max;
        if (*timing->wait_arg < a.args.size()) {
          auto v = resolve(a.args[*timing->wait_arg], m_.insts[idx]);
          if (v) wait = number_value(*v).value_or(wait);
        }
        lo = wait;
        hi = wait + timing->reply_s;
      }
      const double tick = options_.tick_s;
      m_.insts[idx].lo[pl] = static_cast<int>(std::floor(lo / tick + 1e-9));
      m_.insts[idx].hi[pl] = static_cast<int>(std::ceil(hi / tick - 1e-9));
    }
    m_.insts[idx].end_place = m_.places;
    m_.insts[idx].end_inst = static_cast<std::uint32_t>(m_.insts.size());
    return std::nullopt;
  }

 private:
  const Program& program_;
  const BoundOptions& options_;
  Model& m_;
};

bool matches_to(const ActionSpec& a, const BoundQuery& q) {
  if (q.to != BoundQuery::To::Call && q.to != BoundQuery::To::Surface) return false;
  if (a.kind != ActionSpec::Kind::Tactic) return false;
  if (q.to == BoundQuery::To::Surface) return a.tactic == ast::TacticType::Exec && a.target == "surface";
  return a.target == q.to_name && (!q.to_verb || *q.to_verb == a.tactic);
}

std::optional<std::string> finish_model(Model& m, const BoundQuery& q) {
  m.lo.assign(m.places, -1);
  m.hi.assign(m.places, -1);
  m.child.assign(m.places, -1);
  bool event_seen = false;
  bool to_seen = false;
  for (std::uint32_t i = 0; i < m.insts.size(); ++i) {
    const Inst& inst = m.insts[i];
    for (PlaceId pl = 0; pl < inst.an.net.place_count(); ++pl) {
      m.lo[inst.place0 + pl] = inst.lo[pl];
      m.hi[inst.place0 + pl] = inst.hi[pl];
      m.child[inst.place0 + pl] = inst.child[pl];
      if (inst.lo[pl] >= 0) m.timed_places.push_back(inst.place0 + pl);
    }
    for (TransitionId t = 0; t < inst.an.net.transition_count(); ++t) {
      const AnalysisNet::Step& st = inst.an.steps[t];
      GlobalTransition g;
      g.inst = i;
      g.t = t;
      if (st.kind == AnalysisNet::Step::Kind::Outcome) {
        const ActionSpec& a = inst.cn->actions[st.transition][st.action];
        if (a.kind == ActionSpec::Kind::Phase) {
          const PlaceId flight = inst.an.net.inputs(t)[0].node;
          const Inst& child = m.insts[static_cast<std::size_t>(inst.child[flight])];
          g.child_exit = child.place0 + child.cn->exits.at(st.answer);
        } else {
          g.timed = true;
          if (q.from == BoundQuery::From::Fault && a.tactic == ast::TacticType::Ask && a.target == q.from_name) {
            g.ask_answer = st.answer == 0 ? 1 : 0;
            event_seen = true;
          }
        }
      } else if (st.kind == AnalysisNet::Step::Kind::Transition) {
        for (const ActionSpec& a : inst.cn->actions[st.transition]) {
          g.is_to = g.is_to || matches_to(a, q);
          if (q.from == BoundQuery::From::Start && a.kind == ActionSpec::Kind::Phase && a.target == q.from_name) {
            g.is_event = true;
          }
        }
        const GuardNode node = inst.cn->guard_node(st.transition);
        if (q.from == BoundQuery::From::Trip && node.role == GuardRole::Trip &&
            inst.cn->guards[node.guard].name == q.from_name) {
          g.is_event = true;
        }
        to_seen = to_seen || g.is_to;
        event_seen = event_seen || g.is_event;
      }
      m.transitions.push_back(g);
    }
  }
  m.consumers.assign(m.places, {});
  for (std::uint32_t k = 0; k < m.transitions.size(); ++k) {
    const GlobalTransition& g = m.transitions[k];
    const Inst& in = m.insts[g.inst];
    const auto inputs = in.an.net.inputs(g.t);
    if (!inputs.empty()) m.consumers[in.place0 + inputs[0].node].push_back(k);
  }
  const Inst& mission = m.insts.front();
  for (PlaceId e : mission.cn->exits) {
    m.mission_exits.push_back(mission.place0 + e);
    if (q.to == BoundQuery::To::Exit && mission.an.net.place_name(e) == q.to_name) {
      m.to_exit = mission.place0 + e;
      to_seen = true;
    }
  }
  if (!event_seen) {
    switch (q.from) {
      case BoundQuery::From::Fault: return fmt::format("no net asks {}", q.from_name);
      case BoundQuery::From::Trip: return fmt::format("no guard named {} in the mission or its phases", q.from_name);
      case BoundQuery::From::Start: return fmt::format("no PHASE({}) in the mission or its phases", q.from_name);
    }
  }
  if (!to_seen) {
    if (q.to == BoundQuery::To::Exit) return fmt::format("the mission has no exit named {}", q.to_name);
    return q.to == BoundQuery::To::Surface ? std::string("no net calls exec surface")
                                           : fmt::format("no net calls {}", q.to_name);
  }
  return std::nullopt;
}

// ------------------------------------------------------------------ states

constexpr std::uint8_t kStarted = 1;  // the event has happened; time counts
constexpr std::uint8_t kFault = 2;    // the fault is on

struct State {
  std::vector<std::uint8_t> m;
  std::vector<std::uint16_t> c;
  std::uint8_t flags = 0;
  // Before the event: 1 + the instance that issued TO, while it runs (a
  // fault then is answered already, and is not counted); 0 none.
  std::uint16_t covered = 0;
};

std::string encode(const State& s) {
  std::string key;
  key.push_back(static_cast<char>(s.flags));
  key.push_back(static_cast<char>(s.covered & 0xff));
  key.push_back(static_cast<char>(s.covered >> 8));
  for (std::uint32_t p = 0; p < s.m.size(); ++p) {
    if (s.m[p] == 0) continue;
    const std::uint16_t c = s.c[p];
    const char bytes[] = {static_cast<char>(p & 0xff),         static_cast<char>((p >> 8) & 0xff),
                          static_cast<char>((p >> 16) & 0xff), static_cast<char>(s.m[p]),
                          static_cast<char>(c & 0xff),         static_cast<char>(c >> 8)};
    key.append(bytes, sizeof bytes);
  }
  return key;
}

void decode(std::string_view key, State& s) {
  std::fill(s.m.begin(), s.m.end(), 0);
  std::fill(s.c.begin(), s.c.end(), 0);
  s.flags = static_cast<std::uint8_t>(key[0]);
  s.covered =
      static_cast<std::uint16_t>(static_cast<unsigned char>(key[1]) | (static_cast<unsigned char>(key[2]) << 8));
  for (std::size_t i = 3; i + 6 <= key.size(); i += 6) {
    const auto b = [&](std::size_t k) { return static_cast<std::uint32_t>(static_cast<unsigned char>(key[i + k])); };
    const std::uint32_t p = b(0) | (b(1) << 8) | (b(2) << 16);
    s.m[p] = static_cast<std::uint8_t>(b(3));
    s.c[p] = static_cast<std::uint16_t>(b(4) | (b(5) << 8));
  }
}

constexpr std::uint32_t kAdvance = std::numeric_limits<std::uint32_t>::max();
constexpr std::uint32_t kOnset = kAdvance - 1;
constexpr std::uint32_t kTo = std::numeric_limits<std::uint32_t>::max();  // an edge's target: TO happened

struct Edge {
  std::uint32_t to;
  std::uint32_t label;  // a GlobalTransition index, kAdvance or kOnset
  std::uint8_t w;       // ticks counted (after the event)
};

class Explorer {
 public:
  Explorer(const Model& m, const BoundQuery& q, const BoundOptions& o) : m_(m), q_(q), o_(o) {}

  // Builds the graph; false (why in error_) when it is too large or unsupported.
  bool run() {
    urgent_best_.assign(m_.insts.size(), 0);
    State s0;
    s0.m.assign(m_.places, 0);
    s0.c.assign(m_.places, 0);
    load(s0, 0);
    intern(encode(s0), kAdvance, kAdvance);
    State s = s0;
    State next = s0;
    for (std::uint32_t id = 0; id < keys_.size(); ++id) {
      decode(keys_[id], s);
      first_edge_.push_back(static_cast<std::uint32_t>(edges_.size()));
      if (!expand(id, s, next)) return false;
      if (keys_.size() > o_.max_states) {
        error_ = fmt::format("more than {} timed states (--max-states)", o_.max_states);
        return false;
      }
    }
    first_edge_.push_back(static_cast<std::uint32_t>(edges_.size()));
    return true;
  }

  const Model& m_;
  const BoundQuery& q_;
  const BoundOptions& o_;
  std::vector<std::string> keys_;
  std::unordered_map<std::string, std::uint32_t> index_;
  std::vector<std::uint32_t> parent_, parent_label_;  // the BFS tree
  std::vector<std::uint32_t> first_edge_;
  std::vector<Edge> edges_;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> starts_;  // (pre-event state, label) by start state
  std::string error_;

 private:
  std::uint32_t intern(std::string key, std::uint32_t parent, std::uint32_t label) {
    auto [it, fresh] = index_.emplace(std::move(key), static_cast<std::uint32_t>(keys_.size()));
    if (fresh) {
      keys_.push_back(it->first);
      parent_.push_back(parent);
      parent_label_.push_back(label);
      starts_.emplace_back(kAdvance, kAdvance);
    }
    return it->second;
  }

  void clear(State& s, std::uint32_t inst) const {
    const Inst& in = m_.insts[inst];
    if (s.covered > inst && s.covered <= in.end_inst) s.covered = 0;  // the phase that issued TO ended
    std::fill(s.m.begin() + in.place0, s.m.begin() + in.end_place, 0);
    std::fill(s.c.begin() + in.place0, s.c.begin() + in.end_place, 0);
  }
  void load(State& s, std::uint32_t inst) const {
    clear(s, inst);
    const Inst& in = m_.insts[inst];
    const auto& init = in.an.net.initial_marking();
    for (PlaceId p = 0; p < init.size(); ++p)
      s.m[in.place0 + p] = static_cast<std::uint8_t>(std::min<petri::Tokens>(init[p], 255));
  }

  bool enabled(const State& s, const GlobalTransition& g) const {
    const Inst& in = m_.insts[g.inst];
    for (const petri::Arc& a : in.an.net.inputs(g.t)) {
      if (s.m[in.place0 + a.node] < a.weight) return false;
    }
    if (g.child_exit != 0 && s.m[g.child_exit] == 0) return false;
    if (g.timed) {
      const std::uint32_t flight = in.place0 + in.an.net.inputs(g.t)[0].node;
      if (s.c[flight] < m_.lo[flight]) return false;
      if (g.ask_answer >= 0) {
        const bool fault = (s.flags & kFault) != 0;
        if ((g.ask_answer == 1) != (fault == q_.fault_value)) return false;
      }
    }
    return true;
  }

  // Fires g into next (a copy of s); false when a place would overflow or
  // two calls of one place would be in flight at once.
  bool fire(const State& s, const GlobalTransition& g, State& next) {
    next = s;
    const Inst& in = m_.insts[g.inst];
    for (const petri::Arc& a : in.an.net.inputs(g.t)) {
      const std::uint32_t p = in.place0 + a.node;
      next.m[p] = static_cast<std::uint8_t>(next.m[p] - a.weight);
      if (next.m[p] == 0) next.c[p] = 0;
      if (m_.child[p] >= 0 && next.m[p] == 0) clear(next, static_cast<std::uint32_t>(m_.child[p]));
    }
    for (const petri::Arc& a : in.an.net.outputs(g.t)) {
      const std::uint32_t p = in.place0 + a.node;
      if (next.m[p] + a.weight > 255) {
        error_ = fmt::format("{}: place {} holds more than 255 tokens", in.path, in.an.net.place_name(a.node));
        return false;
      }
      const bool flight = m_.lo[p] >= 0 || m_.child[p] >= 0;
      if (flight && next.m[p] > 0) {
        error_ = fmt::format("{}: two calls of {} in flight at once: the timing analysis takes one", in.path,
                             in.an.net.place_name(a.node));
        return false;
      }
      next.m[p] = static_cast<std::uint8_t>(next.m[p] + a.weight);
      if (flight) next.c[p] = 0;
      if (m_.child[p] >= 0) load(next, static_cast<std::uint32_t>(m_.child[p]));
    }
    return true;
  }

  bool ended(const State& s) const {
    for (std::uint32_t e : m_.mission_exits) {
      if (s.m[e] > 0) return true;
    }
    return false;
  }

  void edge(std::uint32_t from, std::uint32_t to, std::uint32_t label, std::uint8_t w) {
    edges_.push_back({to, label, w});
    (void)from;
  }

  void add_successor(std::uint32_t id, const State& next, std::uint32_t label, bool to_now) {
    const bool started = (next.flags & kStarted) != 0;
    if (started && to_now) {
      edge(id, kTo, label, 0);
      return;
    }
    if (started && m_.to_exit && next.m[*m_.to_exit] > 0) {
      edge(id, kTo, label, 0);
      return;
    }
    const std::uint32_t to = intern(encode(next), id, label);
    edge(id, to, label, 0);
  }

  bool expand(std::uint32_t id, const State& s, State& next) {
    if (ended(s)) return true;  // the run is over
    const bool started = (s.flags & kStarted) != 0;
    // Instantaneous steps first: the engine runs them before any reply.
    candidates(s);
    std::vector<std::uint32_t> ready;
    std::fill(urgent_best_.begin(), urgent_best_.end(), std::numeric_limits<int>::min());
    auto& urgent_best = urgent_best_;
    for (std::uint32_t k : candidates_) {
      const GlobalTransition& g = m_.transitions[k];
      if (g.timed || !enabled(s, g)) continue;
      ready.push_back(k);
      const Inst& in = m_.insts[g.inst];
      if (!in.an.urgent.empty() && in.an.urgent[g.t]) {
        urgent_best[g.inst] = std::max(urgent_best[g.inst], in.an.net.priority(g.t));
      }
    }
    if (!ready.empty()) {
      for (std::uint32_t k : ready) {
        const GlobalTransition& g = m_.transitions[k];
        const Inst& in = m_.insts[g.inst];
        if (urgent_best[g.inst] != std::numeric_limits<int>::min() &&
            (!in.an.urgent[g.t] || in.an.net.priority(g.t) != urgent_best[g.inst])) {
          continue;
        }
        if (!fire(s, g, next)) return false;
        if (!started && g.is_to) next.covered = static_cast<std::uint16_t>(g.inst + 1);
        add_successor(id, next, k, g.is_to);
        if (g.is_event && !started) {
          next.flags |= kStarted;
          next.covered = 0;  // meaningful before the event only
          const std::uint32_t before = static_cast<std::uint32_t>(keys_.size());
          add_successor(id, next, k, false);
          note_start(id, k, before);
        }
      }
      return true;
    }
    // Answers, the fault, or time passing.
    bool in_flight = false;
    bool may_wait = true;
    for (std::uint32_t p : m_.timed_places) {
      if (s.m[p] == 0) continue;
      in_flight = true;
      if (s.c[p] >= m_.hi[p]) may_wait = false;
    }
    for (std::uint32_t k : candidates_) {
      const GlobalTransition& g = m_.transitions[k];
      if (!g.timed || !enabled(s, g)) continue;
      if (!fire(s, g, next)) return false;
      add_successor(id, next, k, false);
    }
    if (q_.from == BoundQuery::From::Fault && !started && s.covered == 0) {
      next = s;
      next.flags |= kStarted | kFault;
      const std::uint32_t before = static_cast<std::uint32_t>(keys_.size());
      add_successor(id, next, kOnset, false);
      note_start(id, kOnset, before);
    }
    if (in_flight && may_wait) {
      next = s;
      for (std::uint32_t p : m_.timed_places) {
        if (next.m[p] > 0) ++next.c[p];
      }
      const std::uint32_t to = intern(encode(next), id, kAdvance);
      edge(id, to, kAdvance, started ? 1 : 0);
    }
    return true;
  }

  // The transitions whose first input is marked, in index order.
  void candidates(const State& s) {
    candidates_.clear();
    for (std::uint32_t p = 0; p < s.m.size(); ++p) {
      if (s.m[p] == 0) continue;
      const auto& list = m_.consumers[p];
      candidates_.insert(candidates_.end(), list.begin(), list.end());
    }
    std::sort(candidates_.begin(), candidates_.end());
  }

  std::vector<std::uint32_t> candidates_;
  std::vector<int> urgent_best_;

  // The event's edge just added from `from`: its target is a start state.
  void note_start(std::uint32_t from, std::uint32_t label, std::uint32_t /*fresh_from*/) {
    const Edge& e = edges_.back();
    if (e.to == kTo) {
      immediate_ = true;
      immediate_from_ = {from, label};
      return;
    }
    if (starts_[e.to].first == kAdvance) starts_[e.to] = {from, label};
    start_ids_.push_back(e.to);
  }

 public:
  std::vector<std::uint32_t> start_ids_;
  bool immediate_ = false;  // the event's own step was TO
  std::pair<std::uint32_t, std::uint32_t> immediate_from_{kAdvance, kAdvance};
};

// ------------------------------------------------------------------ the answer

class Solver {
 public:
  Solver(const Explorer& x, const Model& m, const Program& p, const BoundQuery& q, const BoundOptions& o)
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
      a.path.push_back({a.worst_s, "", fmt::format("at the surface (the ascent, at most {:.1f} s)", extra)});
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
      out.push_back(
          {static_cast<double>(elapsed) * tick, "", fmt::format("{:.1f} s pass", static_cast<double>(waited) * tick)});
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

  BoundStep step(std::uint32_t label, std::optional<double> t) const {
    if (label == kOnset) {
      return {
          t, "",
          fmt::format("the fault starts: every ask {} answers {} from now on", q_.from_name, q_.fault_value ? 1 : 0)};
    }
    const GlobalTransition& g = m_.transitions[label];
    const Inst& in = m_.insts[g.inst];
    const AnalysisNet::Step& st = in.an.steps[g.t];
    const CompiledNet& cn = *in.cn;
    const std::string name(cn.net.transition_name(st.transition));
    const auto& actions = cn.actions[st.transition];
    switch (st.kind) {
      case AnalysisNet::Step::Kind::Transition: {
        std::string what = "fires " + name;
        for (std::size_t i = 0; i < actions.size(); ++i) what += (i ? ", " : ": ") + action_text(actions[i]);
        return {t, in.path, what};
      }
      case AnalysisNet::Step::Kind::Outcome: {
        const ActionSpec& a = actions[st.action];
        const char* verb = a.kind == ActionSpec::Kind::Phase ? "ends at" : "answers";
        return {t, in.path, fmt::format("{} {} {}", action_text(a), verb, answer_text(program_, a, st.answer))};
      }
      case AnalysisNet::Step::Kind::Forget:
        return {t, in.path,
                fmt::format("guard {} forgets {}", cn.guards.at(st.answer).name, action_text(actions[st.action]))};
    }
    return {t, in.path, name};
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

  const Explorer& x_;
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

core::Result<BoundQuery> parse_bound(std::string_view text) {
  Cursor c{text};
  BoundQuery q;
  q.text = std::string(text);
  c.skip();
  std::size_t at = c.pos;
  const std::string_view from = c.word();
  if (from == "fault") {
    q.from = BoundQuery::From::Fault;
  } else if (from == "trip") {
    q.from = BoundQuery::From::Trip;
  } else if (from == "start") {
    q.from = BoundQuery::From::Start;
  } else {
    return c.error(at, fmt::format("expected fault, trip or start: {}", kForms));
  }
  at = c.pos;
  std::string_view name = c.word();
  if (q.from == BoundQuery::From::Fault && name == "not") {
    q.fault_value = false;
    at = c.pos;
    name = c.word();
  }
  if (name.empty()) return c.error(at, fmt::format("expected a name after {}", from));
  q.from_name = std::string(name);
  c.skip();
  if (c.text.substr(c.pos, 2) != "->") return c.error(c.pos, fmt::format("expected ->: {}", kForms));
  c.pos += 2;
  c.skip();
  at = c.pos;
  const std::string_view to = c.word();
  if (to == "surface") {
    q.to = BoundQuery::To::Surface;
  } else if (to == "exit") {
    q.to = BoundQuery::To::Exit;
  } else if (to == "call" || to == "exec" || to == "ask" || to == "ood") {
    q.to = BoundQuery::To::Call;
    if (to != "call") q.to_verb = parse_tactic_type(to == "exec" ? "EXEC" : to == "ask" ? "ASK" : "OOD");
  } else {
    return c.error(at, fmt::format("expected exec, ask, ood, call, exit or surface: {}", kForms));
  }
  if (q.to != BoundQuery::To::Surface) {
    at = c.pos;
    name = c.word();
    if (name.empty()) return c.error(at, fmt::format("expected a name after {}", to));
    q.to_name = std::string(name);
  }
  c.skip();
  at = c.pos;
  if (c.word() == "within") {
    c.skip();
    const std::size_t num = c.pos;
    std::size_t end = num;
    while (end < text.size() && (std::isdigit(static_cast<unsigned char>(text[end])) != 0 || text[end] == '.')) ++end;
    double v = 0;
    const auto [ptr, ec] = std::from_chars(text.data() + num, text.data() + end, v);
    if (ec != std::errc{} || ptr != text.data() + end || end == num || !(v > 0) || !std::isfinite(v)) {
      return c.error(num, "expected a number of seconds above 0 after within");
    }
    q.within_s = v;
    c.pos = end;
    c.skip();
    if (c.text.substr(c.pos, 1) == "s") ++c.pos;
    c.skip();
  } else {
    c.pos = at;
  }
  if (c.pos != c.text.size()) return c.error(c.pos, "unexpected text after the question");
  return q;
}

std::string_view bound_verdict_name(BoundAnswer::Verdict v) {
  switch (v) {
    case BoundAnswer::Verdict::Bounded: return "bounded";
    case BoundAnswer::Verdict::Unbounded: return "unbounded";
    case BoundAnswer::Verdict::NoEvent: return "no_event";
    case BoundAnswer::Verdict::Unsupported: return "unsupported";
  }
  return "unsupported";
}

BoundAnswer analyse_bound(const Program& program, const BoundQuery& query, const BoundOptions& options) {
  BoundAnswer a;
  if (!program.mission) {
    a.message = "the timing analysis needs a mission";
    return a;
  }
  Model m;
  const CompiledNet& mission = program.nets[*program.mission];
  Builder b(program, options, m);
  if (auto e = b.add(mission, {}, mission.name, 0)) {
    a.message = *e;
    return a;
  }
  if (auto e = finish_model(m, query)) {
    a.message = *e;
    return a;
  }
  Explorer x(m, query, options);
  if (!x.run()) {
    a.message = x.error_;
    a.states = x.keys_.size();
    return a;
  }
  return Solver(x, m, program, query, options).solve();
}

}  // namespace strata::coral
