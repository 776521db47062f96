#include "petri/explorer.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <limits>
#include <utility>

#include <fmt/format.h>

namespace strata::petri {
namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
constexpr unsigned kMaxBits = 32;  // Tokens are 32-bit

// Where one place's tokens live in a packed marking.
struct Field {
  std::uint32_t word = 0;
  std::uint32_t shift = 0;
  std::uint64_t mask = 0;  // the field's width, at the low bits
};

// A place an arc touches, with the arc's weight.
struct ArcField {
  Field field;
  std::uint64_t weight = 0;
  PlaceId place = 0;
};

inline std::uint64_t get(const std::uint64_t* m, const Field& f) { return (m[f.word] >> f.shift) & f.mask; }
inline void set(std::uint64_t* m, const Field& f, std::uint64_t v) {
  m[f.word] = (m[f.word] & ~(f.mask << f.shift)) | (v << f.shift);
}

inline std::uint64_t mix(std::uint64_t x) {
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

class Explorer {
 public:
  Explorer(const Net& net, const ExploreOptions& options) : net_(net), opt_(options) {}

  ExploreResult run() {
    const std::size_t places = net_.place_count();
    r_.place_bounds.assign(places, 0);
    r_.transition_fired.assign(net_.transition_count(), false);
    bits_.assign(places, 1);
    for (PlaceId p = 0; p < places; ++p) {
      bits_[p] = std::max(1u, static_cast<unsigned>(std::bit_width(net_.initial_marking()[p])));
    }
    relayout();
    table_.assign(1u << 10, 0);
    std::vector<std::uint64_t> initial(words_, 0);
    for (PlaceId p = 0; p < places; ++p) set(initial.data(), fields_[p], net_.initial_marking()[p]);
    insert(initial.data());
    breadth_first();
    r_.states = count_;
    r_.one_safe = r_.max_tokens_in_place <= 1;
    r_.quasi_live = std::all_of(r_.transition_fired.begin(), r_.transition_fired.end(), [](bool b) { return b; });
    r_.memory_bytes = memory();
    r_.words_per_state = words_;
    decide_liveness();
    return std::move(r_);
  }

 private:
  // ---- layout ---------------------------------------------------------------
  void relayout() {
    fields_.resize(bits_.size());
    std::uint32_t word = 0, used = 0;
    for (std::size_t p = 0; p < bits_.size(); ++p) {
      if (used + bits_[p] > 64) {
        ++word;
        used = 0;
      }
      fields_[p] = {word, used, bits_[p] == 64 ? ~0ULL : (1ULL << bits_[p]) - 1};
      used += bits_[p];
    }
    words_ = word + 1;
    in_.clear();
    out_.clear();
    in_begin_.assign(1, 0);
    out_begin_.assign(1, 0);
    for (TransitionId t = 0; t < net_.transition_count(); ++t) {
      for (const Arc& a : net_.inputs(t)) in_.push_back({fields_[a.node], a.weight, a.node});
      for (const Arc& a : net_.outputs(t)) out_.push_back({fields_[a.node], a.weight, a.node});
      in_begin_.push_back(static_cast<std::uint32_t>(in_.size()));
      out_begin_.push_back(static_cast<std::uint32_t>(out_.size()));
    }
  }

  // Place p needs room for `value` tokens: widen its field and re-pack every
  // stored marking. False if it cannot (more than 32 bits).
  bool widen(PlaceId p, std::uint64_t value) {
    unsigned need = static_cast<unsigned>(std::bit_width(value));
    if (need > kMaxBits) return false;
    std::vector<Field> old_fields = fields_;
    const std::uint32_t old_words = words_;
    bits_[p] = std::min(kMaxBits, std::max(need, bits_[p] * 2));
    relayout();
    std::vector<std::uint64_t> packed(static_cast<std::size_t>(count_) * words_, 0);
    for (std::uint64_t s = 0; s < count_; ++s) {
      const std::uint64_t* from = &arena_[s * old_words];
      std::uint64_t* to = &packed[s * words_];
      for (std::size_t q = 0; q < fields_.size(); ++q) set(to, fields_[q], get(from, old_fields[q]));
    }
    arena_ = std::move(packed);
    rehash(table_.size());
    return true;
  }

  // ---- the set of markings ------------------------------------------------------
  std::uint64_t hash(const std::uint64_t* m) const {
    std::uint64_t h = 0x9E3779B97F4A7C15ULL;
    for (std::uint32_t k = 0; k < words_; ++k) h = mix(h ^ m[k]);
    return h;
  }

  // Linear probing from full_hash: the index of m if stored (or kNone), and
  // the slot where the probe stopped (m's, or the empty one for it).
  std::pair<std::uint32_t, std::size_t> probe(const std::uint64_t* m, std::uint64_t full_hash) const {
    const std::size_t mask = table_.size() - 1;
    for (std::size_t h = full_hash & mask;; h = (h + 1) & mask) {
      const std::uint32_t slot = table_[h];
      if (slot == 0) return {kNone, h};
      if (std::memcmp(&arena_[static_cast<std::size_t>(slot - 1) * words_], m, words_ * 8) == 0) return {slot - 1, h};
    }
  }

  std::uint32_t find(const std::uint64_t* m) const { return probe(m, hash(m)).first; }

  void rehash(std::size_t size) {
    table_.assign(size, 0);
    const std::size_t mask = size - 1;
    for (std::uint64_t s = 0; s < count_; ++s) {
      std::size_t h = hash(&arena_[s * words_]) & mask;
      while (table_[h] != 0) h = (h + 1) & mask;
      table_[h] = static_cast<std::uint32_t>(s + 1);
    }
  }

  std::size_t memory() const { return arena_.capacity() * 8 + table_.capacity() * 4; }

  // Adds m if new. Returns false when a limit stops the exploration.
  bool insert(const std::uint64_t* m) { return insert(m, hash(m)); }
  bool insert(const std::uint64_t* m, std::uint64_t full_hash) {
    const auto [found, h] = probe(m, full_hash);
    if (found != kNone) return true;
    if (opt_.max_states && count_ >= opt_.max_states) return stop(fmt::format("stopped at {} states (the limit)", count_));
    if (count_ + 1 >= kNone) return stop("more than 4 294 967 294 states");
    const bool grow_table = (count_ + 1) * 4 > table_.size() * 3;
    if (opt_.max_memory_bytes) {
      std::size_t arena_next = arena_.size() + words_ > arena_.capacity() ? std::max<std::size_t>(arena_.capacity() * 2, 1024)
                                                                         : arena_.capacity();
      std::size_t need = arena_next * 8 + (grow_table ? table_.size() * 8 : table_.size() * 4);
      if (need > opt_.max_memory_bytes) {
        return stop(fmt::format("stopped at {} states: the next step needs {} MB, over --max-memory", count_,
                                need >> 20));
      }
    }
    arena_.insert(arena_.end(), m, m + words_);
    ++count_;
    if (grow_table) {
      rehash(table_.size() * 2);
    } else {
      table_[h] = static_cast<std::uint32_t>(count_);
    }
    return true;
  }

  bool stop(std::string why) {
    if (r_.complete) {
      r_.complete = false;
      r_.stopped_why = std::move(why);
    }
    return false;
  }

  // ---- breadth first --------------------------------------------------------------
  void breadth_first() {
    const std::size_t places = net_.place_count();
    const std::size_t transitions = net_.transition_count();
    std::vector<std::uint64_t> cur;
    std::uint64_t next_progress = opt_.progress_every;
    for (std::uint64_t s = 0; s < count_ && r_.complete; ++s) {
    restart:
      cur.assign(arena_.begin() + static_cast<std::ptrdiff_t>(s * words_),
                 arena_.begin() + static_cast<std::ptrdiff_t>((s + 1) * words_));
      std::uint64_t total = 0;
      for (PlaceId p = 0; p < places; ++p) {
        const std::uint64_t v = get(cur.data(), fields_[p]);
        total += v;
        if (v > r_.place_bounds[p]) r_.place_bounds[p] = static_cast<Tokens>(v);
      }
      r_.max_tokens_per_marking = std::max(r_.max_tokens_per_marking, total);
      // All successors first, their table slots prefetched; then the
      // lookups, which then mostly hit the cache.
      std::uint64_t edges = 0;
      succ_.resize(static_cast<std::size_t>(transitions) * words_);
      hashes_.resize(transitions);
      fired_.clear();
      const std::size_t mask = table_.size() - 1;
      for (TransitionId t = 0; t < transitions; ++t) {
        bool enabled = true;
        for (std::uint32_t i = in_begin_[t]; i < in_begin_[t + 1] && enabled; ++i) {
          enabled = get(cur.data(), in_[i].field) >= in_[i].weight;
        }
        if (!enabled) continue;
        std::uint64_t* succ = &succ_[fired_.size() * words_];
        std::memcpy(succ, cur.data(), words_ * 8);
        for (std::uint32_t i = in_begin_[t]; i < in_begin_[t + 1]; ++i) {
          set(succ, in_[i].field, get(succ, in_[i].field) - in_[i].weight);
        }
        for (std::uint32_t i = out_begin_[t]; i < out_begin_[t + 1]; ++i) {
          const std::uint64_t v = get(succ, out_[i].field) + out_[i].weight;
          if (v > out_[i].field.mask) {
            if (!widen(out_[i].place, v)) {
              stop(fmt::format("place '{}' would hold more than {} tokens", net_.place_name(out_[i].place),
                               kMaxTokens));
              return;
            }
            goto restart;  // the layout changed: this state again, from the start
          }
          set(succ, out_[i].field, v);
        }
        const std::uint64_t h = hash(succ);
        hashes_[fired_.size()] = h;
        __builtin_prefetch(&table_[h & mask]);
        fired_.push_back(t);
      }
      for (std::size_t k = 0; k < fired_.size(); ++k) {
        // The stored marking the slot points to, if any: prefetched too.
        const std::uint32_t slot = table_[hashes_[k] & mask];
        if (slot != 0) __builtin_prefetch(&arena_[static_cast<std::size_t>(slot - 1) * words_]);
      }
      for (std::size_t k = 0; k < fired_.size(); ++k) {
        if (!insert(&succ_[k * words_], hashes_[k])) return;
        ++edges;
        r_.transition_fired[fired_[k]] = true;
      }
      r_.edges += edges;
      if (edges == 0 && !r_.deadlock) {
        r_.deadlock = true;
        r_.first_deadlock = s;
      }
      if (opt_.progress && s + 1 >= next_progress) {
        next_progress += opt_.progress_every;
        if (!opt_.progress({count_, s + 1, r_.edges, memory()})) {
          stop(fmt::format("interrupted after {} states", count_));
          return;
        }
      }
    }
    for (PlaceId p = 0; p < places; ++p) r_.max_tokens_in_place = std::max(r_.max_tokens_in_place, r_.place_bounds[p]);
  }

  // ---- liveness ----------------------------------------------------------------------
  bool enabled(const std::uint64_t* m, TransitionId t) const {
    for (std::uint32_t i = in_begin_[t]; i < in_begin_[t + 1]; ++i) {
      if (get(m, in_[i].field) < in_[i].weight) return false;
    }
    return true;
  }

  // The successor of m by t (enabled, and it fits: the exploration saw it).
  void fire(const std::uint64_t* m, TransitionId t, std::uint64_t* out) const {
    std::memcpy(out, m, words_ * 8);
    for (std::uint32_t i = in_begin_[t]; i < in_begin_[t + 1]; ++i) {
      set(out, in_[i].field, get(out, in_[i].field) - in_[i].weight);
    }
    for (std::uint32_t i = out_begin_[t]; i < out_begin_[t + 1]; ++i) {
      set(out, out_[i].field, get(out, out_[i].field) + out_[i].weight);
    }
  }

  // Live iff every transition is enabled somewhere in every bottom strongly
  // connected component of the reachability graph.
  void decide_liveness() {
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
    if (!opt_.liveness) return;
    const std::uint32_t n = static_cast<std::uint32_t>(count_);
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
      if (index[root] != kNone) continue;
      visit(root);
      while (!calls.empty()) {
        Frame& f = calls.back();
        const std::uint32_t v = f.v;
        const std::uint64_t* m = &arena_[static_cast<std::size_t>(v) * words_];
        bool descended = false;
        while (f.t < transitions) {
          const TransitionId t = f.t++;
          if (!enabled(m, t)) continue;
          fire(m, t, next.data());
          const std::uint32_t w = find(next.data());
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
            const std::uint64_t* mk = &arena_[static_cast<std::size_t>(stack[k]) * words_];
            for (TransitionId t = 0; t < transitions; ++t) {
              if (!seen[t] && enabled(mk, t)) seen[t] = true;
            }
          }
          if (!std::all_of(seen.begin(), seen.end(), [](bool b) { return b; })) {
            r_.live = false;
            return;
          }
        }
        for (std::size_t k = first; k < stack.size(); ++k) on_stack[stack[k]] = false;
        stack.resize(first);
      }
    }
    r_.live = true;
  }

  const Net& net_;
  ExploreOptions opt_;
  ExploreResult r_;
  std::vector<unsigned> bits_;
  std::vector<Field> fields_;
  std::uint32_t words_ = 1;
  std::vector<ArcField> in_, out_;
  std::vector<std::uint32_t> in_begin_, out_begin_;
  std::vector<std::uint64_t> arena_;
  std::vector<std::uint32_t> table_;
  // One state's successors, their hashes and transitions (breadth_first).
  std::vector<std::uint64_t> succ_, hashes_;
  std::vector<TransitionId> fired_;
  std::uint64_t count_ = 0;
};

}  // namespace

ExploreResult explore(const Net& net, const ExploreOptions& options) { return Explorer(net, options).run(); }

}  // namespace strata::petri
