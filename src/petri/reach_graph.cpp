#include "petri/reach_graph.h"

#include <algorithm>
#include <new>

#include <fmt/format.h>

namespace strata::petri {
namespace {

std::uint64_t hash_marking(std::span<const Tokens> m) {
  std::uint64_t h = 0x9e3779b97f4a7c15ULL;
  for (Tokens t : m) {
    h ^= t;
    h *= 0xff51afd7ed558ccdULL;
    h ^= h >> 32;
  }
  return h;
}

// Open addressing over state ids; the markings live in the graph.
class StateIndex {
 public:
  explicit StateIndex(const std::vector<Tokens>& markings, std::size_t places)
      : markings_(markings), places_(places), slots_(1024, kNoState) {}

  // The state holding m, or kNoState; `slot` is where m would go.
  StateId find(std::span<const Tokens> m, std::size_t& slot) const {
    const std::size_t mask = slots_.size() - 1;
    for (slot = hash_marking(m) & mask;; slot = (slot + 1) & mask) {
      StateId s = slots_[slot];
      if (s == kNoState) return kNoState;
      if (std::equal(m.begin(), m.end(), markings_.begin() + static_cast<std::ptrdiff_t>(std::size_t{s} * places_))) {
        return s;
      }
    }
  }

  void insert(StateId s, std::size_t slot, std::size_t count) {
    slots_[slot] = s;
    if (count * 2 > slots_.size()) grow();
  }

  std::size_t bytes() const { return slots_.capacity() * sizeof(StateId); }
  // The bytes the index would need at most to take one more state: its
  // array doubles (old and new both held while it does).
  std::size_t bytes_to_grow(std::size_t count) const { return (count + 1) * 2 > slots_.size() ? bytes() * 2 : 0; }

 private:
  void grow() {
    std::vector<StateId> old(slots_.size() * 2, kNoState);
    old.swap(slots_);
    const std::size_t mask = slots_.size() - 1;
    for (StateId s : old) {
      if (s == kNoState) continue;
      std::span<const Tokens> m{markings_.data() + std::size_t{s} * places_, places_};
      std::size_t slot = hash_marking(m) & mask;
      while (slots_[slot] != kNoState) slot = (slot + 1) & mask;
      slots_[slot] = s;
    }
  }

  const std::vector<Tokens>& markings_;
  std::size_t places_;
  std::vector<StateId> slots_;
};

// Does m cover a (>= everywhere, > somewhere)?
// How far back along its BFS path a new marking is compared: a bound on the
// cost per state. An unbounded net whose repeating cycle is longer than
// this is still stopped, by the state limit.
constexpr unsigned kCoverDepth = 512;

// The bytes a vector would allocate to take `more` elements (while it
// copies, the old array is held too), or 0 when it has room.
template <class V>
std::size_t growth_bytes(const V& v, std::size_t more) {
  if (v.size() + more <= v.capacity()) return 0;
  return std::max(v.capacity() * 2, v.size() + more) * sizeof(typename V::value_type);
}

template <class V>
std::size_t held_bytes(const V& v) {
  return v.capacity() * sizeof(typename V::value_type);
}

// Bytes per state and per edge that a verifier's passes add over the graph.
constexpr std::size_t kPassBytesPerState = 16;
constexpr std::size_t kPassBytesPerEdge = 8;

bool strictly_covers(std::span<const Tokens> m, std::span<const Tokens> a) {
  bool greater = false;
  for (std::size_t p = 0; p < m.size(); ++p) {
    if (m[p] < a[p]) return false;
    greater = greater || m[p] > a[p];
  }
  return greater;
}

}  // namespace

std::size_t ReachGraph::memory_bytes() const {
  return held_bytes(markings_) + held_bytes(parent_) + held_bytes(via_) + held_bytes(edge_begin_) + held_bytes(edges_) +
         is_terminal_place_.size() / 8;
}

std::span<const ReachEdge> ReachGraph::successors(StateId s) const {
  if (s >= explored_) return {};
  return {edges_.data() + edge_begin_[s], edges_.data() + edge_begin_[s + 1]};
}

bool ReachGraph::terminal(StateId s) const {
  std::span<const Tokens> m = marking(s);
  for (std::size_t p = 0; p < places_; ++p) {
    if (m[p] > 0 && is_terminal_place_[p]) return true;
  }
  return false;
}

std::vector<TransitionId> ReachGraph::path_to(StateId s) const {
  std::vector<TransitionId> path;
  for (; parent_[s] != kNoState; s = parent_[s]) path.push_back(via_[s]);
  std::reverse(path.begin(), path.end());
  return path;
}

ReachGraph build_reach_graph(const Net& net, const ReachOptions& options) {
  ReachGraph g;
  const std::size_t places = net.place_count();
  g.places_ = places;
  g.is_terminal_place_.assign(places, false);
  for (PlaceId p : options.terminal_places) g.is_terminal_place_.at(p) = true;

  StateIndex index(g.markings_, places);
  // Would one more state (and its edges) pass the memory limit?
  auto over_memory = [&](std::size_t edges_to_come) {
    if (options.max_memory_bytes == 0) return false;
    const std::size_t states = g.parent_.size() + 1, edges = g.edges_.size() + edges_to_come;
    const std::size_t need = g.memory_bytes() + index.bytes() + growth_bytes(g.markings_, places) +
                             growth_bytes(g.parent_, 1) + growth_bytes(g.via_, 1) + growth_bytes(g.edge_begin_, 1) +
                             growth_bytes(g.edges_, edges_to_come) + index.bytes_to_grow(g.parent_.size()) +
                             states * kPassBytesPerState + edges * kPassBytesPerEdge;
    if (need <= options.max_memory_bytes) return false;
    g.stopped_why_ = fmt::format("stopped at {} markings: the next needs {} MB, over the memory limit",
                                 g.parent_.size(), need >> 20);
    return true;
  };
  bool stop_adding = false;
  auto add = [&](std::span<const Tokens> m, StateId parent, TransitionId via) -> StateId {
    std::size_t slot = 0;
    if (StateId s = index.find(m, slot); s != kNoState) return s;
    if (!g.parent_.empty() && over_memory(net.transition_count())) {
      stop_adding = true;
      return kNoState;
    }
    const auto s = static_cast<StateId>(g.parent_.size());
    g.markings_.insert(g.markings_.end(), m.begin(), m.end());
    g.parent_.push_back(parent);
    g.via_.push_back(via);
    index.insert(s, slot, g.parent_.size());
    return s;
  };
  add(net.initial_marking(), kNoState, 0);
  g.edge_begin_.push_back(0);

  std::vector<Tokens> next(places);
  try {
    for (StateId s = 0; s < g.parent_.size(); ++s) {
      if (g.parent_.size() > options.max_states) {
        g.stopped_why_ = fmt::format("more than {} reachable markings", options.max_states);
        break;
      }
      if ((s & 63) == 0 && std::chrono::steady_clock::now() > options.deadline) {
        g.stopped_why_ = fmt::format("stopped at {} markings: the time limit", g.parent_.size());
        break;
      }
      if (!g.terminal(s)) {
        auto enabled_at = [&](TransitionId t) {
          std::span<const Tokens> m = g.marking(s);
          for (const Arc& a : net.inputs(t)) {
            if (m[a.node] < a.weight) return false;
          }
          return true;
        };
        // An urgent transition enabled: only the urgent ones of its best priority fire.
        std::optional<int> urgent_priority;
        for (TransitionId t = 0; t < options.urgent.size(); ++t) {
          if (!options.urgent[t] || !enabled_at(t)) continue;
          if (!urgent_priority || net.priority(t) > *urgent_priority) urgent_priority = net.priority(t);
        }
        for (TransitionId t = 0; t < net.transition_count(); ++t) {
          if (urgent_priority && (!options.urgent[t] || net.priority(t) != *urgent_priority)) continue;
          if (!enabled_at(t)) continue;
          std::span<const Tokens> m = g.marking(s);
          std::copy(m.begin(), m.end(), next.begin());
          bool overflow = false;
          for (const Arc& a : net.inputs(t)) next[a.node] -= a.weight;
          for (const Arc& a : net.outputs(t)) {
            overflow = overflow || next[a.node] > kMaxTokens - a.weight;
            if (!overflow) next[a.node] += a.weight;
          }
          if (overflow) {
            g.stopped_why_ =
                fmt::format("firing {} would put more than {} tokens in a place", net.transition_name(t), kMaxTokens);
            break;
          }
          const std::size_t before = g.parent_.size();
          StateId target = add(next, s, t);
          if (stop_adding) break;
          g.edges_.push_back({t, target});
          if (g.parent_.size() == before || g.terminal(target)) continue;
          // A new marking that can go on: does it cover one of its recent
          // ancestors? (A terminal one cannot repeat anything.)
          StateId a = s;
          for (unsigned depth = 0; a != kNoState && depth < kCoverDepth; a = g.parent_[a], ++depth) {
            if (strictly_covers(g.marking(target), g.marking(a))) {
              g.unbounded_ = Unbounded{target, a};
              g.stopped_why_ = "the net is unbounded";
              break;
            }
          }
          if (g.unbounded_) break;
        }
      }
      if (!g.stopped_why_.empty()) {
        // s was not expanded in full: it stays unexplored.
        g.edges_.resize(g.edge_begin_[s]);
        break;
      }
      g.edge_begin_.push_back(g.edges_.size());
      g.explored_ = s + 1;
    }
  } catch (const std::bad_alloc&) {
    // Keep what is whole: the states every array holds, the edges of the
    // states explored in full.
    const std::size_t n =
        std::min({g.parent_.size(), g.via_.size(), g.markings_.size() / std::max<std::size_t>(places, 1)});
    g.parent_.resize(n);
    g.via_.resize(n);
    g.markings_.resize(n * places);
    g.edge_begin_.resize(g.explored_ + 1);
    g.edges_.resize(g.edge_begin_[g.explored_]);
    g.stopped_why_ = fmt::format("stopped at {} markings: out of memory", n);
  }
  g.complete_ = g.stopped_why_.empty();
  return g;
}

}  // namespace strata::petri
