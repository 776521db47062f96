#include "petri/invariants.h"

#include <algorithm>
#include <numeric>
#include <optional>

#include <fmt/format.h>

namespace strata::petri {
namespace {

// A sparse vector: (index, value) sorted by index, no zero values.
using SfEntries = std::vector<std::pair<std::uint32_t, std::int64_t>>;

// One row of the Farkas matrix: y over the groups of places, and what is
// left of y.C over the columns not eliminated yet.
struct SfRow {
  SfEntries c;  // by TransitionId
  SfEntries y;  // by group
};

std::int64_t sf_at(const SfEntries& v, std::uint32_t index) {
  auto it = std::lower_bound(v.begin(), v.end(), index, [](const auto& e, std::uint32_t i) { return e.first < i; });
  return it != v.end() && it->first == index ? it->second : 0;
}

// supp(a.y) within supp(b.y).
bool sf_support_within(const SfRow& a, const SfRow& b) {
  if (a.y.size() > b.y.size()) return false;
  std::size_t j = 0;
  for (const auto& [i, v] : a.y) {
    while (j < b.y.size() && b.y[j].first < i) ++j;
    if (j == b.y.size() || b.y[j].first != i) return false;
  }
  return true;
}

// ka * a + kb * b over sorted entries, zeros dropped; false on overflow.
bool sf_lin(const SfEntries& a, std::int64_t ka, const SfEntries& b, std::int64_t kb, SfEntries& out, std::int64_t& g) {
  out.clear();
  out.reserve(a.size() + b.size());
  std::size_t i = 0, j = 0;
  while (i < a.size() || j < b.size()) {
    std::uint32_t index = 0;
    std::int64_t u = 0, v = 0, r = 0;
    if (j == b.size() || (i < a.size() && a[i].first < b[j].first)) {
      index = a[i].first;
      if (__builtin_mul_overflow(ka, a[i++].second, &u)) return false;
    } else if (i == a.size() || b[j].first < a[i].first) {
      index = b[j].first;
      if (__builtin_mul_overflow(kb, b[j++].second, &v)) return false;
    } else {
      index = a[i].first;
      if (__builtin_mul_overflow(ka, a[i++].second, &u) || __builtin_mul_overflow(kb, b[j++].second, &v)) return false;
    }
    if (__builtin_add_overflow(u, v, &r)) return false;
    if (r == 0) continue;
    g = std::gcd(g, r);
    out.emplace_back(index, r);
  }
  return true;
}

bool sf_combine(const SfRow& a, std::int64_t ka, const SfRow& b, std::int64_t kb, SfRow& out) {
  std::int64_t g = 0;
  if (!sf_lin(a.c, ka, b.c, kb, out.c, g) || !sf_lin(a.y, ka, b.y, kb, out.y, g)) return false;
  if (g > 1) {
    for (auto& e : out.c) e.second /= g;
    for (auto& e : out.y) e.second /= g;
  }
  return true;
}

std::size_t sf_bytes(const SfRow& r) { return sizeof(SfRow) + (r.c.capacity() + r.y.capacity()) * 16; }

struct SfUnionFind {
  std::vector<std::uint32_t> parent, size;
  explicit SfUnionFind(std::size_t n) : parent(n), size(n, 1) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t find(std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  bool unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    if (size[a] < size[b]) std::swap(a, b);
    parent[b] = a;
    size[a] += size[b];
    return true;
  }
};

// Farkas over the rows of one component, against the limits.
class SfFarkas {
 public:
  SfFarkas(const SemiflowLimits& limits, std::size_t transitions)
      : limits_(limits), pos_(transitions, 0), neg_(transitions, 0) {}

  // Eliminates every column of rows; the minimal semiflows are left in
  // rows. False (with why()) when a limit stopped it.
  bool run(std::vector<SfRow>& rows) {
    for (;;) {
      std::optional<std::uint32_t> t = next_column(rows);
      if (!t) return true;
      if (!eliminate(rows, *t)) return false;
    }
  }

  const std::string& why() const { return why_; }

 private:
  // The column that makes the fewest new rows, or none when every c is 0.
  std::optional<std::uint32_t> next_column(const std::vector<SfRow>& rows) {
    std::vector<std::uint32_t> touched;
    for (const SfRow& r : rows) {
      for (const auto& [t, v] : r.c) {
        if (pos_[t] == 0 && neg_[t] == 0) touched.push_back(t);
        ++(v > 0 ? pos_[t] : neg_[t]);
      }
      work_ += r.c.size();
    }
    std::optional<std::uint32_t> best;
    std::int64_t best_cost = 0;
    for (std::uint32_t t : touched) {
      const auto p = static_cast<std::int64_t>(pos_[t]), n = static_cast<std::int64_t>(neg_[t]);
      const std::int64_t cost = p * n - p - n;
      if (!best || cost < best_cost || (cost == best_cost && t < *best)) {
        best = t;
        best_cost = cost;
      }
      pos_[t] = neg_[t] = 0;
    }
    return best;
  }

  bool stop(std::string why) {
    why_ = std::move(why);
    return false;
  }

  bool over_limits(std::size_t rows, std::size_t bytes) {
    if (rows > limits_.max_rows) return stop(fmt::format("more than {} rows", limits_.max_rows));
    if (work_ > limits_.max_work) return stop(fmt::format("more than {} matrix entries touched", limits_.max_work));
    if (limits_.max_memory_bytes && bytes > limits_.max_memory_bytes)
      return stop(fmt::format("the rows would need more than {} MB", limits_.max_memory_bytes >> 20));
    if ((++checks_ & 255) == 0 && std::chrono::steady_clock::now() > limits_.deadline) return stop("the time limit");
    return true;
  }

  bool eliminate(std::vector<SfRow>& rows, std::uint32_t t) {
    std::vector<SfRow> next;
    std::vector<const SfRow*> pos, neg;
    std::size_t bytes = 0;
    for (SfRow& r : rows) {
      const std::int64_t v = sf_at(r.c, t);
      if (v == 0) {
        bytes += sf_bytes(r);
        next.push_back(std::move(r));
      } else {
        (v > 0 ? pos : neg).push_back(&r);
      }
    }
    for (const SfRow* a : pos) {
      for (const SfRow* b : neg) {
        SfRow r;
        if (!sf_combine(*a, -sf_at(b->c, t), *b, sf_at(a->c, t), r)) {
          return stop("a coefficient would overflow 64 bits");
        }
        work_ += a->c.size() + a->y.size() + b->c.size() + b->y.size();
        // Keep only rows of minimal support: the rows kept from before are
        // minimal among themselves; a new row is compared with all.
        bool redundant = false;
        for (const SfRow& other : next) {
          work_ += other.y.size();
          if (sf_support_within(other, r)) {
            redundant = true;
            break;
          }
        }
        if (!redundant) {
          for (std::size_t k = 0; k < next.size(); ++k) {
            if (!sf_support_within(r, next[k])) continue;
            bytes -= sf_bytes(next[k]);
            next[k] = std::move(next.back());
            next.pop_back();
            --k;
          }
          bytes += sf_bytes(r);
          next.push_back(std::move(r));
        }
        if (!over_limits(next.size(), bytes + rows_bytes(pos) + rows_bytes(neg))) return false;
      }
    }
    // pos and neg point into rows: swap only now.
    rows = std::move(next);
    return true;
  }

  static std::size_t rows_bytes(const std::vector<const SfRow*>& rows) {
    std::size_t n = 0;
    for (const SfRow* r : rows) n += sf_bytes(*r);
    return n;
  }

  const SemiflowLimits& limits_;
  std::vector<std::uint32_t> pos_, neg_;  // by TransitionId, 0 between calls
  std::uint64_t work_ = 0;
  std::uint64_t checks_ = 0;
  std::string why_;
};

}  // namespace

Semiflows p_semiflows(const Net& net, const SemiflowLimits& limits) {
  const std::size_t places = net.place_count();
  const std::size_t transitions = net.transition_count();
  Semiflows result;
  result.covered.assign(places, false);
  auto stopped = [&](std::string why) {
    result.complete = false;
    result.stopped_why = std::move(why);
    result.flows.clear();
    return std::move(result);
  };

  // Each transition's column of C, sparse: (place, Post - Pre).
  auto column = [&](TransitionId t) {
    SfEntries col;
    for (const Arc& a : net.inputs(t)) col.emplace_back(a.node, -static_cast<std::int64_t>(a.weight));
    for (const Arc& a : net.outputs(t)) col.emplace_back(a.node, static_cast<std::int64_t>(a.weight));
    std::sort(col.begin(), col.end());
    SfEntries merged;
    for (const auto& e : col) {
      if (!merged.empty() && merged.back().first == e.first)
        merged.back().second += e.second;
      else
        merged.push_back(e);
    }
    std::erase_if(merged, [](const auto& e) { return e.second == 0; });
    return merged;
  };

  // 1. Contraction of the steps of chains (-w at one place, +w at another).
  SfUnionFind groups(places);
  std::vector<bool> contracted(transitions, false);
  for (TransitionId t = 0; t < transitions; ++t) {
    const SfEntries col = column(t);
    if (col.empty()) {
      contracted[t] = true;  // no constraint
    } else if (col.size() == 2 && col[0].second == -col[1].second) {
      groups.unite(col[0].first, col[1].first);
      contracted[t] = true;
    }
  }
  std::vector<std::uint32_t> group_of(places), group_root;  // dense group ids
  {
    std::vector<std::uint32_t> id(places, UINT32_MAX);
    for (PlaceId p = 0; p < places; ++p) {
      const std::uint32_t root = groups.find(p);
      if (id[root] == UINT32_MAX) {
        id[root] = static_cast<std::uint32_t>(group_root.size());
        group_root.push_back(root);
      }
      group_of[p] = id[root];
    }
  }
  const std::size_t group_count = group_root.size();

  // The groups' rows: y = the group (weight 1 on each of its places), c =
  // the sum of its places' rows over the columns left.
  std::vector<SfRow> rows(group_count);
  std::size_t bytes = 0;
  for (TransitionId t = 0; t < transitions; ++t) {
    if (contracted[t]) continue;
    for (const auto& [p, v] : column(t)) rows[group_of[p]].c.emplace_back(t, v);
  }
  for (std::uint32_t g = 0; g < group_count; ++g) {
    SfEntries& c = rows[g].c;  // sorted by t already; merge a group's places
    SfEntries merged;
    for (const auto& e : c) {
      if (!merged.empty() && merged.back().first == e.first)
        merged.back().second += e.second;
      else
        merged.push_back(e);
    }
    std::erase_if(merged, [](const auto& e) { return e.second == 0; });
    c = std::move(merged);
    rows[g].y = {{g, 1}};
    bytes += sf_bytes(rows[g]);
  }
  if (limits.max_memory_bytes && bytes > limits.max_memory_bytes) {
    return stopped(fmt::format("the rows would need more than {} MB", limits.max_memory_bytes >> 20));
  }

  // 2. Components: groups linked by a column left.
  SfUnionFind linked(group_count);
  {
    std::vector<std::uint32_t> first(transitions, UINT32_MAX);
    for (std::uint32_t g = 0; g < group_count; ++g) {
      for (const auto& [t, v] : rows[g].c) {
        if (first[t] == UINT32_MAX)
          first[t] = g;
        else
          linked.unite(first[t], g);
      }
    }
  }
  std::vector<std::vector<std::uint32_t>> members(group_count);
  for (std::uint32_t g = 0; g < group_count; ++g) members[linked.find(g)].push_back(g);

  // 3. Farkas on each component.
  std::vector<SfRow> found;
  SfFarkas farkas(limits, transitions);
  for (const auto& component : members) {
    if (component.empty()) continue;
    std::vector<SfRow> part;
    part.reserve(component.size());
    for (std::uint32_t g : component) part.push_back(std::move(rows[g]));
    if (!farkas.run(part)) return stopped(farkas.why());
    for (SfRow& r : part) found.push_back(std::move(r));
  }

  // Groups back to places.
  std::vector<std::vector<PlaceId>> places_of(group_count);
  for (PlaceId p = 0; p < places; ++p) places_of[group_of[p]].push_back(p);
  for (const SfRow& r : found) {
    Semiflow f;
    for (const auto& [g, w] : r.y) {
      for (PlaceId p : places_of[g]) {
        f.weights.emplace_back(p, static_cast<std::uint64_t>(w));
        f.constant += static_cast<std::uint64_t>(w) * net.initial_marking()[p];
        result.covered[p] = true;
      }
    }
    std::sort(f.weights.begin(), f.weights.end());
    result.flows.push_back(std::move(f));
  }
  std::sort(result.flows.begin(), result.flows.end(),
            [](const Semiflow& a, const Semiflow& b) { return a.weights < b.weights; });
  return result;
}

Semiflows p_semiflows(const Net& net, std::size_t max_rows, std::uint64_t max_work) {
  SemiflowLimits limits;
  limits.max_rows = max_rows;
  limits.max_work = max_work;
  return p_semiflows(net, limits);
}

bool is_p_invariant(const Net& net, const std::vector<std::pair<PlaceId, std::uint64_t>>& weights) {
  std::vector<std::int64_t> y(net.place_count(), 0);
  for (auto [p, w] : weights) y.at(p) += static_cast<std::int64_t>(w);
  for (TransitionId t = 0; t < net.transition_count(); ++t) {
    std::int64_t sum = 0;
    for (const Arc& a : net.inputs(t)) sum -= y[a.node] * a.weight;
    for (const Arc& a : net.outputs(t)) sum += y[a.node] * a.weight;
    if (sum != 0) return false;
  }
  return true;
}

}  // namespace strata::petri
