#include "petri/explorer.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include "petri/net_families.h"

namespace strata::petri {
namespace {

std::uint64_t pow3(unsigned n) {
  std::uint64_t r = 1;
  while (n-- > 0) r *= 3;
  return r;
}

TEST(Explorer, ASingleTransitionCycle) {
  NetBuilder b;
  PlaceId p = b.add_place("p", 1);
  PlaceId q = b.add_place("q");
  TransitionId t = b.add_transition("t");
  TransitionId u = b.add_transition("u");
  b.add_input(t, p);
  b.add_output(t, q);
  b.add_input(u, q);
  b.add_output(u, p);
  ExploreResult r = explore(std::move(b).build());
  EXPECT_TRUE(r.complete);
  EXPECT_EQ(2u, r.states);
  EXPECT_EQ(2u, r.edges);
  EXPECT_EQ(1u, r.max_tokens_in_place);
  EXPECT_EQ(1u, r.max_tokens_per_marking);
  EXPECT_FALSE(r.deadlock);
  EXPECT_TRUE(r.one_safe);
  EXPECT_TRUE(r.quasi_live);
  EXPECT_EQ(std::optional<bool>(true), r.live);
}

TEST(Explorer, ADeadlockAndADeadTransition) {
  NetBuilder b;
  PlaceId p = b.add_place("p", 1);
  PlaceId q = b.add_place("q");
  PlaceId never = b.add_place("never");
  TransitionId t = b.add_transition("t");
  TransitionId dead = b.add_transition("dead");
  b.add_input(t, p);
  b.add_output(t, q);
  b.add_input(dead, never);
  ExploreResult r = explore(std::move(b).build());
  EXPECT_EQ(2u, r.states);
  EXPECT_EQ(1u, r.edges);
  EXPECT_TRUE(r.deadlock);
  ASSERT_TRUE(r.first_deadlock.has_value());
  EXPECT_EQ(1u, *r.first_deadlock);
  EXPECT_FALSE(r.quasi_live);
  EXPECT_FALSE(r.transition_fired[dead]);
  EXPECT_EQ(std::optional<bool>(false), r.live);
}

// A producer adds 3 tokens per firing to `buffer` (place 1) until `budget`
// (place 0, 100) runs out: 101 states, the buffer's field widens from 1 bit
// to 9.
Net widening_producer() {
  NetBuilder b;
  PlaceId budget = b.add_place("budget", 100);
  PlaceId buffer = b.add_place("buffer");
  TransitionId produce = b.add_transition("produce");
  b.add_input(produce, budget);
  b.add_output(produce, buffer, 3);
  return std::move(b).build();
}

TEST(Explorer, WeightsAndFieldsThatWiden) {
  const PlaceId budget = 0, buffer = 1;
  ExploreResult r = explore(widening_producer());
  EXPECT_EQ(101u, r.states);
  EXPECT_EQ(100u, r.edges);
  EXPECT_EQ(300u, r.max_tokens_in_place);
  EXPECT_EQ(300u, r.place_bounds[buffer]);
  EXPECT_EQ(100u, r.place_bounds[budget]);
  EXPECT_EQ(300u, r.max_tokens_per_marking);
  EXPECT_FALSE(r.one_safe);
  EXPECT_TRUE(r.deadlock);
}

TEST(Explorer, WithoutStatisticsTheStatesEdgesAndDeadlockAreTheSame) {
  // What a deadlock question reads; the producer's field still widens.
  for (const Net& net : {dining_philosophers(5), referendum(6), widening_producer()}) {
    ExploreOptions with;
    with.liveness = false;
    ExploreOptions without = with;
    without.statistics = false;
    const ExploreResult a = explore(net, with), r = explore(net, without);
    EXPECT_TRUE(r.complete);
    EXPECT_EQ(a.states, r.states);
    EXPECT_EQ(a.edges, r.edges);
    EXPECT_EQ(a.deadlock, r.deadlock);
    EXPECT_EQ(a.first_deadlock, r.first_deadlock);
    EXPECT_FALSE(r.live.has_value());
  }
}

TEST(Explorer, LiveOnlyIfEveryBottomComponentEnablesEverything) {
  // From s, `left` leads into a cycle a<->b and `right` into a cycle c<->d:
  // both bottom components miss transitions, so the net is not live though
  // every transition fires somewhere.
  NetBuilder b;
  PlaceId s = b.add_place("s", 1);
  PlaceId a = b.add_place("a"), bb = b.add_place("b"), c = b.add_place("c"), d = b.add_place("d");
  auto arc = [&](const char* name, PlaceId from, PlaceId to) {
    TransitionId t = b.add_transition(name);
    b.add_input(t, from);
    b.add_output(t, to);
  };
  arc("left", s, a);
  arc("right", s, c);
  arc("ab", a, bb);
  arc("ba", bb, a);
  arc("cd", c, d);
  arc("dc", d, c);
  ExploreResult r = explore(std::move(b).build());
  EXPECT_EQ(5u, r.states);
  EXPECT_TRUE(r.quasi_live);
  EXPECT_FALSE(r.deadlock);
  EXPECT_EQ(std::optional<bool>(false), r.live);
}

TEST(Explorer, PhilosophersHave3PowNStates) {
  for (unsigned n : {2u, 3u, 5u, 7u}) {
    ExploreResult r = explore(dining_philosophers(n));
    EXPECT_EQ(pow3(n), r.states) << n;
    EXPECT_TRUE(r.deadlock) << "everyone holds a left fork";
    EXPECT_TRUE(r.one_safe);
    EXPECT_TRUE(r.quasi_live);
    EXPECT_EQ(std::optional<bool>(false), r.live);
  }
}

TEST(Explorer, ReferendumHas3PowNPlus1States) {
  for (unsigned n : {2u, 4u, 6u, 9u}) {
    ExploreResult r = explore(referendum(n));
    EXPECT_EQ(pow3(n) + 1, r.states) << n;
    EXPECT_TRUE(r.deadlock);
    EXPECT_TRUE(r.one_safe);
    EXPECT_EQ(n, r.max_tokens_per_marking) << "every voter holds one token";
  }
}

TEST(Explorer, TheTableAndQueuePeakUnder22BytesAStateOnReferendum12) {
  // 531,442 states of one word; the table doubles from 4 MB to 8 MB at
  // 393,217, with about 130,000 markings queued. Holding the old and the
  // new table at once, and a ring queue that doubled (old and new ring), the
  // peak was over 14 MB: 26 bytes a state.
  ExploreResult r = explore(referendum(12));
  ASSERT_EQ(pow3(12) + 1, r.states);
  ASSERT_EQ(1u, r.words_per_state);
  EXPECT_EQ(std::size_t{8} << 20, r.memory_bytes - (r.memory_bytes & ((std::size_t{1} << 20) - 1)))
      << "the table at the end: 2^20 slots";
  EXPECT_GE(r.peak_memory_bytes, r.memory_bytes);
  EXPECT_LE(static_cast<double>(r.peak_memory_bytes) / static_cast<double>(r.states), 22.0)
      << r.peak_memory_bytes << " bytes at the peak";
}

TEST(Explorer, FieldsWidenedBeforeTheSemiflowBoundsAreRepackedToThem) {
  // Ten voters each vote yes or no once; a vote moves a token from the
  // budget (20) to the count. count + budget = 20 is a P-semiflow, but the
  // explorer only uses it after 2^15 states: until then the count's field
  // widens from 1 bit as the votes come, then it is re-packed as 5 bits.
  NetBuilder b;
  const PlaceId budget = b.add_place("budget", 20);
  const PlaceId count = b.add_place("count");
  for (int i = 0; i < 10; ++i) {
    const PlaceId ready = b.add_place(fmt::format("ready{}", i), 1);
    for (const char* vote : {"yes", "no"}) {
      const PlaceId voted = b.add_place(fmt::format("{}{}", vote, i));
      const TransitionId t = b.add_transition(fmt::format("vote_{}{}", vote, i));
      b.add_input(t, ready);
      b.add_input(t, budget);
      b.add_output(t, voted);
      b.add_output(t, count);
    }
  }
  ExploreResult r = explore(std::move(b).build());
  ASSERT_TRUE(r.complete);
  EXPECT_EQ(pow3(10), r.states);
  EXPECT_EQ(std::uint64_t{20} * pow3(9), r.edges) << "two votes for each voter still ready, in every state";
  EXPECT_EQ(20u, r.place_bounds[budget]);
  EXPECT_EQ(10u, r.place_bounds[count]);
  EXPECT_EQ(20u, r.max_tokens_in_place);
  EXPECT_EQ(30u, r.max_tokens_per_marking);
  EXPECT_TRUE(r.deadlock);
  EXPECT_FALSE(r.one_safe);
  EXPECT_TRUE(r.quasi_live);
  EXPECT_EQ(std::optional<bool>(false), r.live);
}

TEST(Explorer, LimitsStopWithAPartialResult) {
  ExploreOptions o;
  o.max_states = 50;
  ExploreResult r = explore(dining_philosophers(6), o);
  EXPECT_FALSE(r.complete);
  EXPECT_EQ(50u, r.states);
  EXPECT_FALSE(r.live.has_value()) << "not decided on a partial graph";
  EXPECT_NE(std::string::npos, r.stopped_why.find("50 states")) << r.stopped_why;

  ExploreOptions m;
  m.max_memory_bytes = std::size_t{64} << 10;
  ExploreResult rm = explore(dining_philosophers(10), m);
  EXPECT_FALSE(rm.complete);
  EXPECT_LT(rm.states, pow3(10));
  EXPECT_NE(std::string::npos, rm.stopped_why.find("--max-memory")) << rm.stopped_why;
  EXPECT_LE(rm.memory_bytes, 64u * 1024u);

  int calls = 0;
  ExploreOptions p;
  p.progress_every = 100;
  p.progress = [&](const ExploreProgress& at) {
    ++calls;
    return at.explored < 300;
  };
  ExploreResult rp = explore(dining_philosophers(8), p);
  EXPECT_FALSE(rp.complete);
  EXPECT_EQ(3, calls);
  EXPECT_NE(std::string::npos, rp.stopped_why.find("interrupted")) << rp.stopped_why;
}

// Regression (issue 19): no time limit; and the memory count left out the
// old table while a new one filled, so the peak passed --max-memory.
TEST(Explorer, ATimeLimitStopsItWithAPartialResult) {
  ExploreOptions o;
  o.deadline = std::chrono::steady_clock::now() - std::chrono::seconds(1);
  ExploreResult r = explore(dining_philosophers(10), o);
  EXPECT_FALSE(r.complete);
  EXPECT_LT(r.states, pow3(10));
  EXPECT_NE(std::string::npos, r.stopped_why.find("the time limit")) << r.stopped_why;
  EXPECT_FALSE(r.live.has_value());
}

// Regression: the progress callback (Ctrl-C's way in) was asked only every
// progress_every states, 2^20 by default: under ThreadSanitizer that was 30 s
// and more, and `strata verify --pnml` did not stop on Ctrl-C in time. It is
// now asked at least every tenth of a second, whatever the count.
TEST(Explorer, TheProgressCallbackIsAskedOftenHoweverSlowlyStatesCome) {
  ExploreOptions o;
  o.progress_every = std::uint64_t{1} << 40;  // never, by the count
  int calls = 0;
  o.progress = [&](const ExploreProgress&) { return ++calls < 2; };
  const auto start = std::chrono::steady_clock::now();
  ExploreResult r = explore(referendum(15), o);  // 14,348,908 states: seconds in any build
  EXPECT_FALSE(r.complete);
  EXPECT_EQ(2, calls);
  EXPECT_LT(r.states, pow3(15) + 1);
  EXPECT_NE(std::string::npos, r.stopped_why.find("interrupted after ")) << r.stopped_why;
  std::printf("stopped after %.0f ms, %llu states\n",
              std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count(),
              static_cast<unsigned long long>(r.states));
}

TEST(Explorer, AGrowingTableCountsItsOldCopyAgainstTheMemoryLimit) {
  constexpr std::size_t kLimit = std::size_t{1} << 20;
  ExploreOptions m;
  m.max_memory_bytes = kLimit;
  ExploreResult r = explore(dining_philosophers(10), m);
  EXPECT_FALSE(r.complete);
  // What it holds at the end, and the doubling that did not happen: the
  // old table (r.memory_bytes) and a new one twice its size, over the limit.
  EXPECT_LE(r.memory_bytes, kLimit);
  EXPECT_GT(r.memory_bytes * 3, kLimit) << "stopped far too early";
}

TEST(Explorer, FieldsWidenWhenNoSemiflowBoundsThePlace) {
  // `small` takes 1 token from budget (100) and puts 3 in buffer, `big`
  // takes 2 and puts 1: no P-semiflow covers the places, so their fields
  // start at the initial tokens' width and widen, several times, with many
  // markings stored and queued. The states are (100 - i - 2j, 3i + j) for
  // i + 2j <= 100, all distinct: 2601 of them.
  NetBuilder b;
  PlaceId budget = b.add_place("budget", 100);
  PlaceId buffer = b.add_place("buffer");
  TransitionId small = b.add_transition("small");
  b.add_input(small, budget);
  b.add_output(small, buffer, 3);
  TransitionId big = b.add_transition("big");
  b.add_input(big, budget, 2);
  b.add_output(big, buffer, 1);
  ExploreResult r = explore(std::move(b).build());
  EXPECT_TRUE(r.complete);
  EXPECT_EQ(2601u, r.states);
  EXPECT_EQ(2550u + 2500u, r.edges) << "small where budget >= 1, big where budget >= 2";
  EXPECT_EQ(300u, r.place_bounds[buffer]);
  EXPECT_EQ(100u, r.place_bounds[budget]);
  EXPECT_EQ(300u, r.max_tokens_per_marking);
  EXPECT_TRUE(r.deadlock);
  EXPECT_EQ(std::optional<bool>(false), r.live);
}

TEST(Explorer, LivenessWhenTheInitialMarkingIsNotReachedAgain) {
  // Neither net comes back to its initial marking, so the backward search
  // from it does not cover the graph and the bottom components decide.
  // Not live: start fires once, then a and c swap a token for ever.
  NetBuilder b;
  PlaceId s = b.add_place("s", 1);
  PlaceId a = b.add_place("a"), c = b.add_place("c");
  auto arc = [](NetBuilder& nb, const char* name, PlaceId from, PlaceId to) {
    TransitionId t = nb.add_transition(name);
    nb.add_input(t, from);
    nb.add_output(t, to);
  };
  arc(b, "start", s, a);
  arc(b, "ac", a, c);
  arc(b, "ca", c, a);
  ExploreResult r = explore(std::move(b).build());
  EXPECT_EQ(3u, r.states);
  EXPECT_TRUE(r.quasi_live);
  EXPECT_FALSE(r.deadlock);
  EXPECT_EQ(std::optional<bool>(false), r.live);

  // Live: (p, d) -t-> (q, d) -u-> (p, c) -t-> (q, c) -x-> (q, d): the last
  // three form the only bottom component, where t, u and x all fire; the
  // initial (p, d) is never marked again.
  NetBuilder l;
  PlaceId p = l.add_place("p", 1), q = l.add_place("q"), cc = l.add_place("c"), d = l.add_place("d", 1);
  TransitionId t = l.add_transition("t");
  l.add_input(t, p);
  l.add_output(t, q);
  TransitionId u = l.add_transition("u");
  l.add_input(u, q);
  l.add_input(u, d);
  l.add_output(u, p);
  l.add_output(u, cc);
  TransitionId x = l.add_transition("x");
  l.add_input(x, q);
  l.add_input(x, cc);
  l.add_output(x, q);
  l.add_output(x, d);
  ExploreResult rl = explore(std::move(l).build());
  EXPECT_EQ(4u, rl.states);
  EXPECT_TRUE(rl.quasi_live);
  EXPECT_FALSE(rl.deadlock);
  EXPECT_EQ(std::optional<bool>(true), rl.live);
}

// ---- against a plain reference: a std::map of markings, breadth first ------

struct Reference {
  std::vector<Marking> states;  // breadth-first order
  std::vector<std::vector<std::uint32_t>> succ;
  std::uint64_t edges = 0;
  std::vector<Tokens> bounds;
  std::uint64_t max_total = 0;
  std::optional<std::uint64_t> first_deadlock;
  std::vector<bool> fired;
  bool complete = true;
};

Reference reference(const Net& net, std::size_t limit) {
  Reference r;
  std::map<Marking, std::uint32_t> index;
  r.bounds.assign(net.place_count(), 0);
  r.fired.assign(net.transition_count(), false);
  r.states.push_back(net.initial_marking());
  index[net.initial_marking()] = 0;
  for (std::size_t s = 0; s < r.states.size(); ++s) {
    const Marking m = r.states[s];
    std::uint64_t total = 0;
    for (PlaceId p = 0; p < m.size(); ++p) {
      r.bounds[p] = std::max(r.bounds[p], m[p]);
      total += m[p];
    }
    r.max_total = std::max(r.max_total, total);
    r.succ.emplace_back();
    for (TransitionId t = 0; t < net.transition_count(); ++t) {
      bool enabled = true;
      for (const Arc& a : net.inputs(t)) enabled = enabled && m[a.node] >= a.weight;
      if (!enabled) continue;
      Marking next = m;
      for (const Arc& a : net.inputs(t)) next[a.node] -= a.weight;
      for (const Arc& a : net.outputs(t)) next[a.node] += a.weight;
      auto [it, added] = index.emplace(next, static_cast<std::uint32_t>(r.states.size()));
      if (added) {
        if (r.states.size() >= limit) {
          r.complete = false;
          return r;
        }
        r.states.push_back(next);
      }
      r.succ.back().push_back(it->second);
      r.fired[t] = true;
      ++r.edges;
    }
    if (r.succ.back().empty() && !r.first_deadlock) r.first_deadlock = s;
  }
  return r;
}

// Live: from every state, every transition is enabled in some state it
// reaches.
bool reference_live(const Net& net, const Reference& r) {
  for (std::size_t s = 0; s < r.states.size(); ++s) {
    std::vector<bool> seen(r.states.size(), false), enabled(net.transition_count(), false);
    std::vector<std::uint32_t> todo{static_cast<std::uint32_t>(s)};
    seen[s] = true;
    while (!todo.empty()) {
      const std::uint32_t v = todo.back();
      todo.pop_back();
      for (TransitionId t = 0; t < net.transition_count(); ++t) {
        bool e = true;
        for (const Arc& a : net.inputs(t)) e = e && r.states[v][a.node] >= a.weight;
        enabled[t] = enabled[t] || e;
      }
      for (std::uint32_t w : r.succ[v]) {
        if (!seen[w]) {
          seen[w] = true;
          todo.push_back(w);
        }
      }
    }
    if (!std::all_of(enabled.begin(), enabled.end(), [](bool b) { return b; })) return false;
  }
  return true;
}

RC_GTEST_PROP(ExplorerProperty, AgreesWithAPlainBreadthFirstSearch, ()) {
  const auto places = *rc::gen::inRange<std::size_t>(1, 7);
  const auto transitions = *rc::gen::inRange<std::size_t>(1, 7);
  NetBuilder b;
  for (std::size_t p = 0; p < places; ++p) b.add_place(fmt::format("p{}", p), *rc::gen::inRange<Tokens>(0, 4));
  // Half the nets move tokens around (as many in as out, weight 1 when
  // `conservative`): bounded, often live; the others mostly grow or die.
  const bool conservative = *rc::gen::arbitrary<bool>();
  for (std::size_t t = 0; t < transitions; ++t) {
    TransitionId id = b.add_transition(fmt::format("t{}", t));
    if (conservative) {
      const auto arcs = *rc::gen::inRange<std::size_t>(1, 3);
      for (std::size_t a = 0; a < arcs; ++a) {
        b.add_input(id, static_cast<PlaceId>(*rc::gen::inRange<std::size_t>(0, places)));
        b.add_output(id, static_cast<PlaceId>(*rc::gen::inRange<std::size_t>(0, places)));
      }
      continue;
    }
    const auto arcs = *rc::gen::inRange<std::size_t>(1, 5);
    for (std::size_t a = 0; a < arcs; ++a) {
      const auto p = static_cast<PlaceId>(*rc::gen::inRange<std::size_t>(0, places));
      const auto w = *rc::gen::inRange<std::uint32_t>(1, 4);
      if (*rc::gen::arbitrary<bool>()) {
        b.add_input(id, p, w);
      } else {
        b.add_output(id, p, w);
      }
    }
  }
  const Net net = std::move(b).build();
  constexpr std::size_t kLimit = 300;
  const Reference ref = reference(net, kLimit);
  ExploreOptions o;
  o.max_states = kLimit;
  const ExploreResult r = explore(net, o);
  RC_ASSERT(r.complete == ref.complete);
  if (!ref.complete) {
    RC_TAG("over the limit");
    RC_ASSERT(r.states == kLimit);
    return;
  }
  RC_ASSERT(r.states == ref.states.size());
  RC_ASSERT(r.edges == ref.edges);
  RC_ASSERT(r.place_bounds == ref.bounds);
  RC_ASSERT(r.max_tokens_per_marking == ref.max_total);
  RC_ASSERT(r.max_tokens_in_place == *std::max_element(ref.bounds.begin(), ref.bounds.end()));
  RC_ASSERT(r.deadlock == ref.first_deadlock.has_value());
  RC_ASSERT(r.first_deadlock == ref.first_deadlock);
  RC_ASSERT(r.transition_fired == ref.fired);
  RC_ASSERT(r.live.has_value());
  const bool live = reference_live(net, ref);
  RC_TAG(live ? "live" : "not live");
  RC_ASSERT(*r.live == live);
}

}  // namespace
}  // namespace strata::petri
