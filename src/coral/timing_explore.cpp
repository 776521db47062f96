// The timing analysis's graph (coral/timing.h): the model's timed states,
// in discrete time, and the steps between them.
#include <algorithm>
#include <limits>
#include <unordered_map>

#include <fmt/format.h>

#include "coral/timing_internal.h"

namespace strata::coral::timing_detail {
namespace {

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

class Explorer : public TimedGraph {
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
  std::unordered_map<std::string, std::uint32_t> index_;

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
};

}  // namespace

bool explore(const Model& m, const BoundQuery& q, const BoundOptions& o, TimedGraph& g) {
  Explorer x(m, q, o);
  const bool ok = x.run();
  g = std::move(static_cast<TimedGraph&>(x));
  return ok;
}

}  // namespace strata::coral::timing_detail
