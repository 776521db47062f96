#include "petri/invariants.h"

#include <algorithm>
#include <numeric>

namespace strata::petri {
namespace {

struct Row {
  std::vector<std::int64_t> c;  // the remaining columns of y.C
  std::vector<std::int64_t> y;  // by PlaceId
};

bool support_within(const Row& a, const Row& b) {  // supp(a) within supp(b)
  for (std::size_t p = 0; p < a.y.size(); ++p) {
    if (a.y[p] != 0 && b.y[p] == 0) return false;
  }
  return true;
}

// ka * a + kb * b, divided by the gcd of its entries; false on overflow.
bool combine(const Row& a, std::int64_t ka, const Row& b, std::int64_t kb, Row& out) {
  out.c.resize(a.c.size());
  out.y.resize(a.y.size());
  std::int64_t g = 0;
  auto lin = [&](std::int64_t x, std::int64_t y, std::int64_t& r) {
    std::int64_t u = 0, v = 0;
    if (__builtin_mul_overflow(ka, x, &u) || __builtin_mul_overflow(kb, y, &v) || __builtin_add_overflow(u, v, &r)) {
      return false;
    }
    g = std::gcd(g, r);
    return true;
  };
  for (std::size_t i = 0; i < a.c.size(); ++i) {
    if (!lin(a.c[i], b.c[i], out.c[i])) return false;
  }
  for (std::size_t i = 0; i < a.y.size(); ++i) {
    if (!lin(a.y[i], b.y[i], out.y[i])) return false;
  }
  if (g > 1) {
    for (auto& x : out.c) x /= g;
    for (auto& x : out.y) x /= g;
  }
  return true;
}

}  // namespace

Semiflows p_semiflows(const Net& net, std::size_t max_rows, std::uint64_t max_work) {
  const std::size_t places = net.place_count();
  const std::size_t transitions = net.transition_count();
  Semiflows result;
  result.covered.assign(places, false);

  std::vector<Row> rows(places);
  for (PlaceId p = 0; p < places; ++p) {
    rows[p].c.resize(transitions);
    for (TransitionId t = 0; t < transitions; ++t) rows[p].c[t] = net.incidence(p, t);
    rows[p].y.assign(places, 0);
    rows[p].y[p] = 1;
  }

  std::uint64_t work = 0;  // entries touched, for max_work
  for (TransitionId t = 0; t < transitions && result.complete; ++t) {
    std::vector<Row> next;
    std::vector<const Row*> pos, neg;
    for (const Row& r : rows) {
      if (r.c[t] == 0)
        next.push_back(r);
      else
        (r.c[t] > 0 ? pos : neg).push_back(&r);
    }
    for (const Row* a : pos) {
      for (const Row* b : neg) {
        Row r;
        work += places + transitions + next.size() * places;
        if (!combine(*a, -b->c[t], *b, a->c[t], r) || next.size() >= max_rows || work > max_work) {
          result.complete = false;
          break;
        }
        // Keep only rows of minimal support.
        bool redundant = false;
        for (const Row& other : next) {
          if (support_within(other, r)) {
            redundant = true;
            break;
          }
        }
        if (redundant) continue;
        std::erase_if(next, [&](const Row& other) { return support_within(r, other); });
        next.push_back(std::move(r));
      }
      if (!result.complete) break;
    }
    rows = std::move(next);
  }
  if (!result.complete) return result;

  for (const Row& r : rows) {
    Semiflow f;
    for (PlaceId p = 0; p < places; ++p) {
      if (r.y[p] == 0) continue;
      f.weights.emplace_back(p, static_cast<std::uint64_t>(r.y[p]));
      f.constant += static_cast<std::uint64_t>(r.y[p]) * net.initial_marking()[p];
      result.covered[p] = true;
    }
    result.flows.push_back(std::move(f));
  }
  std::sort(result.flows.begin(), result.flows.end(),
            [](const Semiflow& a, const Semiflow& b) { return a.weights < b.weights; });
  return result;
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
