// The liveness pass of the explorer (explorer_internal.h).
#include <algorithm>
#include <cstring>
#include <optional>
#include <vector>

#include <fmt/format.h>

#include "petri/explorer_internal.h"

namespace strata::petri::explorer_detail {

bool Explorer::enabled(const std::uint64_t* m, TransitionId t) const {
  for (std::uint32_t i = in_begin_[t]; i < in_begin_[t + 1]; ++i) {
    if (get(m, in_[i].field) < in_[i].weight) return false;
  }
  return true;
}

void Explorer::fire(const std::uint64_t* m, TransitionId t, std::uint64_t* out) const {
  std::memcpy(out, m, words_ * sizeof(std::uint64_t));
  for (std::uint32_t d = delta_begin_[t]; d < delta_begin_[t + 1]; ++d) {
    out[deltas_[d].word] = out[deltas_[d].word] - deltas_[d].sub + deltas_[d].add;
  }
}

void Explorer::decide_liveness() {
  const std::size_t transitions = net_.transition_count();
  if (!r_.complete) return;
  if (transitions == 0) {
    r_.live = true;
    return;
  }
  if (r_.deadlock || !r_.quasi_live) {
    r_.live = false;
    return;
  }
  if (!opt_.liveness) {
    r_.live_why = "the liveness pass was not asked for";
    return;
  }
  // The passes' arrays beside the table: a bit per slot and 4 bytes per
  // state for the backward search; for Tarjan 8 bytes and 2 bits per slot,
  // and its stacks (up to 12 bytes per state, doubled while they grow).
  const std::size_t backward = slots_ / 8 + count_ * 4;
  const std::size_t tarjan = slots_ * 8 + slots_ / 4 + count_ * 24;
  if (!fits(memory() + backward)) {
    r_.live_why = fmt::format("the liveness pass needs {} MB more, over the memory limit", backward >> 20);
    return;
  }
  // Every transition fires somewhere: when every state reaches the initial
  // one, the graph is one component, bottom, and the net is live.
  const std::optional<bool> strongly_connected = words_ == 1   ? all_reach_initial<1>()
                                                 : words_ == 2 ? all_reach_initial<2>()
                                                               : all_reach_initial<0>();
  const char* stopped = "the time limit, in the liveness pass";
  if (!strongly_connected) {
    r_.live_why = interrupted_ ? "interrupted, in the liveness pass" : stopped;
    return;
  }
  if (*strongly_connected) {
    r_.live = true;
    return;
  }
  if (!fits(memory() + tarjan)) {
    r_.live_why = fmt::format("the liveness pass needs {} MB more, over the memory limit", tarjan >> 20);
    return;
  }
  r_.live = bottom_components_enable_all();
  if (!r_.live) r_.live_why = interrupted_ ? "interrupted, in the liveness pass" : stopped;
}

template <unsigned W>
std::optional<bool> Explorer::all_reach_initial() {
  const std::uint32_t words = W ? W : words_;
  std::vector<std::uint64_t> seen((slots_ + 63) / 64, 0);
  // Slots to visit, breadth first; the markings a few places ahead are
  // prefetched.
  std::vector<std::uint32_t> queue;
  queue.reserve(count_);
  constexpr std::size_t kAhead = 8;
  const std::vector<std::uint64_t> initial = pack_initial();
  const std::uint32_t root = find<W>(initial.data(), hash<W>(initial.data()));
  if (root == kNone) return false;  // cannot happen
  seen[root / 64] |= 1ULL << (root % 64);
  queue.push_back(root);
  Batch* now = &batches_[0];
  Batch* next = &batches_[1];
  expand_back<W>(marking(root), *now);
  for (std::size_t head = 0; head < queue.size(); ++head) {
    if (past_deadline()) return std::nullopt;
    // Pipelined as breadth_first: the next state's predecessors first.
    if (head + kAhead < queue.size()) __builtin_prefetch(marking(queue[head + kAhead]));
    const bool ahead = head + 1 < queue.size();
    if (ahead) expand_back<W>(marking(queue[head + 1]), *next);
    for (std::size_t k = 0; k < now->n; ++k) {
      const std::uint32_t v = find<W>(&now->succ[k * words], now->hashes[k]);
      if (v == kNone || (seen[v / 64] >> (v % 64) & 1)) continue;
      seen[v / 64] |= 1ULL << (v % 64);
      queue.push_back(v);
    }
    if (ahead) {
      std::swap(now, next);
    } else if (head + 1 < queue.size()) {
      expand_back<W>(marking(queue[head + 1]), *now);
    }
  }
  const std::uint64_t reached = queue.size();
  return reached == count_;
}

template <unsigned W>
void Explorer::expand_back(const std::uint64_t* m, Batch& b) {
  const std::uint32_t words = W ? W : words_;
  const std::size_t transitions = net_.transition_count();
  b.succ.resize(transitions * words + words);
  b.hashes.resize(transitions);
  std::size_t n = 0;
  for (TransitionId t = 0; t < transitions; ++t) {
    bool ok = true;
    for (std::uint32_t i = back_begin_[t]; i < back_begin_[t + 1] && ok; ++i) {
      const std::uint64_t x = m[back_[i].word];
      ok = (x & back_[i].set) == back_[i].set && (x & back_[i].clear) == 0;
    }
    for (std::uint32_t i = back_wide_begin_[t]; i < back_wide_begin_[t + 1] && ok; ++i) {
      const Touch& c = back_wide_[i];
      const std::uint64_t v = get(m, c.field);
      ok = v >= c.post && v - c.post + c.pre <= c.field.mask;
    }
    if (!ok) continue;
    std::uint64_t* pred = &b.succ[n * words];
    for (std::uint32_t k = 0; k < words; ++k) pred[k] = m[k];
    for (std::uint32_t d = delta_begin_[t]; d < delta_begin_[t + 1]; ++d) {
      pred[deltas_[d].word] = pred[deltas_[d].word] - deltas_[d].add + deltas_[d].sub;
    }
    const std::uint64_t h = hash<W>(pred);
    b.hashes[n] = h;
    __builtin_prefetch(&table_[slot_of(h) * words]);
    ++n;
  }
  b.n = n;
}

std::optional<bool> Explorer::bottom_components_enable_all() {
  const std::size_t transitions = net_.transition_count();
  const std::uint32_t n = static_cast<std::uint32_t>(slots_);
  std::vector<std::uint32_t> index(n, kNone), low(n, 0);
  std::vector<bool> on_stack(n, false), leaves(n, false);
  std::vector<std::uint32_t> stack;
  struct Frame {
    std::uint32_t v;
    TransitionId t;
  };
  std::vector<Frame> calls;
  std::vector<std::uint64_t> next(words_);
  std::vector<bool> seen(transitions);
  std::uint32_t counter = 0;
  auto visit = [&](std::uint32_t v) {
    index[v] = low[v] = counter++;
    stack.push_back(v);
    on_stack[v] = true;
    calls.push_back({v, 0});
  };
  for (std::uint32_t root = 0; root < n; ++root) {
    if (index[root] != kNone || *marking(root) == kEmpty) continue;
    visit(root);
    while (!calls.empty()) {
      if (past_deadline()) return std::nullopt;
      Frame& f = calls.back();
      const std::uint32_t v = f.v;
      const std::uint64_t* m = marking(v);
      bool descended = false;
      while (f.t < transitions) {
        const TransitionId t = f.t++;
        if (!enabled(m, t)) continue;
        fire(m, t, next.data());
        const std::uint32_t w = find<0>(next.data(), hash<0>(next.data()));
        if (index[w] == kNone) {
          visit(w);  // f is invalid from here
          descended = true;
          break;
        }
        if (on_stack[w]) {
          low[v] = std::min(low[v], index[w]);
        } else {
          leaves[v] = true;  // an edge into a finished component
        }
      }
      if (descended) continue;
      calls.pop_back();
      if (!calls.empty()) {
        const std::uint32_t parent = calls.back().v;
        low[parent] = std::min(low[parent], low[v]);
        if (!on_stack[v] || low[v] == index[v]) leaves[parent] = true;  // v's component is finished
      }
      if (low[v] != index[v]) continue;
      // v roots a component: pop it; bottom when no member leaves it.
      bool bottom = true;
      std::fill(seen.begin(), seen.end(), false);
      std::size_t first = stack.size();
      do {
        --first;
      } while (stack[first] != v);
      for (std::size_t k = first; k < stack.size(); ++k) bottom = bottom && !leaves[stack[k]];
      if (bottom) {
        for (std::size_t k = first; k < stack.size(); ++k) {
          const std::uint64_t* mk = marking(stack[k]);
          for (TransitionId t = 0; t < transitions; ++t) {
            if (!seen[t] && enabled(mk, t)) seen[t] = true;
          }
        }
        if (!std::all_of(seen.begin(), seen.end(), [](bool b) { return b; })) return false;
      }
      for (std::size_t k = first; k < stack.size(); ++k) on_stack[stack[k]] = false;
      stack.resize(first);
    }
  }
  return true;
}

}  // namespace strata::petri::explorer_detail
