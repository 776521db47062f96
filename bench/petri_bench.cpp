// Firing throughput of petri::State, whose enabled set is kept up to date
// incrementally, against a naive baseline that rescans the transitions in rank
// order with petri::is_enabled after each firing. One benchmark iteration is
// one firing, so items_per_second reads as firings per second.
//
// Nets, built once per shape and size outside the timed loops:
//   ring   - n places, n transitions t_i: p_i -> p_(i+1 mod n), 8 tokens.
//            Firings walk along the ring: good locality.
//   random - a random marked graph: n transitions with 2 input and 2 output
//            places each, 2n places each written by one transition and read
//            by one, the successor transitions drawn from two random
//            permutations, place ids shuffled, priorities 0..3. One token on
//            every arc that goes from a transition to one of lower or equal
//            id marks every cycle, so the net is live by construction
//            (a marked graph is live iff every cycle holds a token, and firing
//            keeps each cycle's count); n more tokens go on random places.
//            Firings touch places and transitions all over the net.
//            (A net with n places read by two transitions each and 2n random
//            tokens, which needs no such argument, deadlocked within a few
//            hundred firings at n = 100 and within the run at n = 10^4.)
// Choices:
//   first  - enabled().first(): highest priority, then declaration order;
//            the naive runner returns the first enabled transition it meets.
//   random - enabled().at(rng % size) with a fixed seed, the honest worst case
//            for cache locality; the naive runner collects every enabled
//            transition and picks one the same way.
// Both runners start from the same warmed-up marking, reached by the
// incremental runner with the same choice from the initial marking, so a
// short naive run at 10^6 is not measured in an atypical start state. On the
// ring, about 4.5n first-choice firings gather the 8 tokens on p_(n-1); from
// then on one token at a time runs a lap alone (n firings) and rejoins the
// others, so n/2 more firings leave it half way round, where the naive scan
// costs its average over a lap (n/2 transitions). The random net gets 4n.
// Before any timing, the two runners are checked to make the same first-choice
// firings from the initial marking and to agree on the enabled set.
// A deadlock or a failed firing stops the benchmark with SkipWithError rather
// than reporting a figure for work that was not done.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <memory>
#include <numeric>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "petri/net.h"
#include "petri/state.h"

namespace strata::petri {
namespace {

enum class Shape { kRing, kRandom };
enum class Choice { kFirst, kRandom };

constexpr std::uint64_t kNetSeed = 0x5eed'0001;
constexpr std::uint64_t kChoiceSeed = 0x5eed'0002;
constexpr std::uint64_t kWarmupSeed = 0x5eed'0003;
constexpr std::size_t kRingTokens = 8;
constexpr int kRandomPriorityLevels = 4;
// The naive scan costs O(n) per firing: at 10^6 a fixed, small count keeps
// the binary's run time bounded.
constexpr benchmark::IterationCount kNaiveIterationsAtMillion = 100;

// splitmix64: small, fast, and the same sequence on every platform.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(seed) {}

  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  // Uniform in [0, n) for n < 2^32 (multiply-shift, no division).
  std::uint32_t below(std::size_t n) { return static_cast<std::uint32_t>(((next() >> 32) * n) >> 32); }

 private:
  std::uint64_t state_;
};

std::vector<std::uint32_t> random_permutation(std::size_t n, Rng& rng) {
  std::vector<std::uint32_t> v(n);
  std::iota(v.begin(), v.end(), 0U);
  for (std::size_t i = n; i > 1; --i) std::swap(v[i - 1], v[rng.below(i)]);
  return v;
}

// Makes b[t] != a[t] for every t by swapping with the next slot; keeps b a
// permutation. Needs n >= 2.
void make_distinct(const std::vector<std::uint32_t>& a, std::vector<std::uint32_t>& b) {
  const std::size_t n = a.size();
  for (std::size_t t = 0; t < n; ++t) {
    if (b[t] == a[t]) std::swap(b[t], b[(t + 1) % n]);
  }
}

Net make_ring(std::size_t n) {
  NetBuilder b;
  b.reserve(n, n, n);
  Marking initial(n, 0);
  for (std::size_t k = 0; k < kRingTokens; ++k) ++initial[k * n / kRingTokens];
  for (std::size_t i = 0; i < n; ++i) b.add_place(fmt::format("p{}", i), initial[i]);
  for (std::size_t i = 0; i < n; ++i) {
    auto t = b.add_transition(fmt::format("t{}", i));
    b.add_input(t, static_cast<PlaceId>(i));
    b.add_output(t, static_cast<PlaceId>((i + 1) % n));
  }
  return std::move(b).build();
}

Net make_random(std::size_t n) {
  Rng rng(kNetSeed);
  // Transition t writes places 2t and 2t+1 (before shuffling), read by
  // succ1[t] and succ2[t]; both are permutations, so every transition has
  // exactly two inputs and every weak component is strongly connected.
  std::vector<std::uint32_t> succ1 = random_permutation(n, rng);
  std::vector<std::uint32_t> succ2 = random_permutation(n, rng);
  make_distinct(succ1, succ2);
  const std::vector<std::uint32_t> place_of = random_permutation(2 * n, rng);

  Marking initial(2 * n, 0);
  for (std::size_t t = 0; t < n; ++t) {
    if (succ1[t] <= t) initial[place_of[2 * t]] = 1;
    if (succ2[t] <= t) initial[place_of[2 * t + 1]] = 1;
  }
  for (std::size_t k = 0; k < n; ++k) ++initial[rng.below(2 * n)];

  NetBuilder b;
  b.reserve(2 * n, n, 2 * n);
  for (std::size_t i = 0; i < 2 * n; ++i) b.add_place(fmt::format("p{}", i), initial[i]);
  for (std::size_t i = 0; i < n; ++i) {
    b.add_transition(fmt::format("t{}", i), static_cast<int>(rng.below(kRandomPriorityLevels)));
  }
  for (std::size_t i = 0; i < n; ++i) {
    const auto t = static_cast<TransitionId>(i);
    b.add_output(t, place_of[2 * i]);
    b.add_output(t, place_of[2 * i + 1]);
    b.add_input(succ1[i], place_of[2 * i]);
    b.add_input(succ2[i], place_of[2 * i + 1]);
  }
  return std::move(b).build();
}

// The baseline: a plain marking, the paper's enabling rule, and a scan of the
// transitions in rank order after every firing.
class NaiveRunner {
 public:
  NaiveRunner(const Net& net, const std::vector<TransitionId>& by_rank, Marking marking)
      : net_(net), by_rank_(by_rank), marking_(std::move(marking)) {}

  const Marking& marking() const { return marking_; }

  std::optional<TransitionId> first_enabled() const {
    for (TransitionId t : by_rank_) {
      if (is_enabled(net_, marking_, t)) return t;
    }
    return std::nullopt;
  }

  // Every enabled transition, in rank order.
  void collect_enabled(std::vector<TransitionId>& out) const {
    out.clear();
    for (TransitionId t : by_rank_) {
      if (is_enabled(net_, marking_, t)) out.push_back(t);
    }
  }

  // x(p) - w(p,t) + w(t,p). Precondition: t is enabled. The generated nets
  // conserve tokens, so no overflow check.
  void fire(TransitionId t) {
    for (const Arc& a : net_.inputs(t)) marking_[a.node] -= a.weight;
    for (const Arc& a : net_.outputs(t)) marking_[a.node] += a.weight;
  }

 private:
  const Net& net_;
  const std::vector<TransitionId>& by_rank_;
  Marking marking_;
};

// The incremental runner's choice, shared by the benchmark and the warm-up.
template <Choice kChoice>
TransitionId choose(const EnabledSet& enabled, Rng& rng) {
  if constexpr (kChoice == Choice::kFirst)
    return *enabled.first();
  else
    return enabled.at(rng.below(enabled.size()));
}

struct BenchNet {
  Net net;
  std::vector<TransitionId> by_rank;  // highest priority first, then lowest id
  std::size_t warmup_firings = 0;
  std::string problem;             // non-empty: the net failed a check
  std::optional<Marking> warm[2];  // per Choice, computed on first use
};

// Fires `steps` times with first-choice in both runners and checks they make
// the same choices, reach the same marking and agree on the enabled set.
std::string cross_check(const Net& net, const std::vector<TransitionId>& by_rank, std::size_t steps) {
  State incremental(net);
  NaiveRunner naive(net, by_rank, net.initial_marking());
  for (std::size_t i = 0; i < steps; ++i) {
    auto a = incremental.enabled().first();
    auto b = naive.first_enabled();
    if (a != b) return fmt::format("incremental and naive choices differ at firing {}", i);
    if (!a) return fmt::format("deadlock after {} firings", i);
    if (!incremental.fire(*a).ok()) return fmt::format("firing {} failed", i);
    naive.fire(*b);
  }
  if (incremental.marking() != naive.marking()) return "markings differ after the cross-check";
  std::vector<TransitionId> enabled;
  naive.collect_enabled(enabled);
  if (incremental.enabled().sorted() != enabled) return "enabled sets differ after the cross-check";
  return {};
}

BenchNet& bench_net(Shape shape, std::size_t n) {
  static std::map<std::pair<Shape, std::size_t>, std::unique_ptr<BenchNet>> cache;
  auto& slot = cache[{shape, n}];
  if (!slot) {
    slot = std::make_unique<BenchNet>();
    slot->net = shape == Shape::kRing ? make_ring(n) : make_random(n);
    slot->warmup_firings = shape == Shape::kRing ? n * 5 : n * 4;
    const Net& net = slot->net;
    slot->by_rank.resize(n);
    std::iota(slot->by_rank.begin(), slot->by_rank.end(), TransitionId{0});
    std::stable_sort(slot->by_rank.begin(), slot->by_rank.end(),
                     [&](TransitionId a, TransitionId b) { return net.priority(a) > net.priority(b); });
    slot->problem = cross_check(net, slot->by_rank, n >= 1'000'000 ? 200 : 20'000);
  }
  return *slot;
}

// The marking after the warm-up firings with kChoice from the initial
// marking, or nullptr (with bn.problem set) if the warm-up failed.
template <Choice kChoice>
const Marking* warm_marking(BenchNet& bn) {
  auto& warm = bn.warm[static_cast<int>(kChoice)];
  if (!warm && bn.problem.empty()) {
    State s(bn.net);
    Rng rng(kWarmupSeed);
    for (std::size_t i = 0; i < bn.warmup_firings; ++i) {
      if (s.enabled().empty()) {
        bn.problem = fmt::format("deadlock after {} warm-up firings", i);
        return nullptr;
      }
      if (!s.fire(choose<kChoice>(s.enabled(), rng)).ok()) {
        bn.problem = fmt::format("warm-up firing {} failed", i);
        return nullptr;
      }
    }
    warm = s.marking();
  }
  return warm ? &*warm : nullptr;
}

template <Choice kChoice>
void bm_incremental(benchmark::State& st, Shape shape) {
  BenchNet& bn = bench_net(shape, static_cast<std::size_t>(st.range(0)));
  const Marking* start = warm_marking<kChoice>(bn);
  if (!start) {
    st.SkipWithError(bn.problem.c_str());
    return;
  }
  State s(bn.net, *start);
  Rng rng(kChoiceSeed);
  for (auto _ : st) {
    if (s.enabled().empty()) {
      st.SkipWithError("deadlock: no transition is enabled");
      break;
    }
    if (!s.fire(choose<kChoice>(s.enabled(), rng)).ok()) {
      st.SkipWithError("a firing failed (overflow)");
      break;
    }
  }
  st.SetItemsProcessed(st.iterations());
  st.counters["bytes_per_arc"] = benchmark::Counter(static_cast<double>(bn.net.memory_bytes() + s.memory_bytes()) /
                                                    static_cast<double>(bn.net.arc_count()));
  st.counters["enabled_at_end"] = benchmark::Counter(static_cast<double>(s.enabled().size()));
}

template <Choice kChoice>
void bm_naive(benchmark::State& st, Shape shape) {
  BenchNet& bn = bench_net(shape, static_cast<std::size_t>(st.range(0)));
  const Marking* start = warm_marking<kChoice>(bn);
  if (!start) {
    st.SkipWithError(bn.problem.c_str());
    return;
  }
  NaiveRunner runner(bn.net, bn.by_rank, *start);
  Rng rng(kChoiceSeed);
  std::vector<TransitionId> enabled;
  enabled.reserve(bn.net.transition_count());
  for (auto _ : st) {
    std::optional<TransitionId> t;
    if constexpr (kChoice == Choice::kFirst) {
      t = runner.first_enabled();
    } else {
      runner.collect_enabled(enabled);
      if (!enabled.empty()) t = enabled[rng.below(enabled.size())];
    }
    if (!t) {
      st.SkipWithError("deadlock: no transition is enabled");
      break;
    }
    runner.fire(*t);
  }
  st.SetItemsProcessed(st.iterations());
}

void register_all() {
  constexpr std::int64_t kSizes[] = {100, 10'000, 1'000'000};
  const std::pair<Shape, const char*> shapes[] = {{Shape::kRing, "ring"}, {Shape::kRandom, "random"}};
  for (const auto& [shape, shape_name] : shapes) {
    for (Choice choice : {Choice::kFirst, Choice::kRandom}) {
      const std::string prefix = std::string("fire/") + shape_name + (choice == Choice::kFirst ? "/first" : "/random");
      for (std::int64_t n : kSizes) {
        const Shape s = shape;  // a lambda cannot capture a structured binding in GCC 12
        auto* inc = benchmark::RegisterBenchmark((prefix + "/incremental").c_str(), [s, choice](benchmark::State& st) {
          if (choice == Choice::kFirst)
            bm_incremental<Choice::kFirst>(st, s);
          else
            bm_incremental<Choice::kRandom>(st, s);
        });
        inc->ArgName("n")->Arg(n)->MinTime(0.3);
        auto* naive = benchmark::RegisterBenchmark((prefix + "/naive").c_str(), [s, choice](benchmark::State& st) {
          if (choice == Choice::kFirst)
            bm_naive<Choice::kFirst>(st, s);
          else
            bm_naive<Choice::kRandom>(st, s);
        });
        naive->ArgName("n")->Arg(n);
        if (n >= 1'000'000)
          naive->Iterations(kNaiveIterationsAtMillion);
        else
          naive->MinTime(0.2);
      }
    }
  }
}

}  // namespace
}  // namespace strata::petri

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  strata::petri::register_all();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
