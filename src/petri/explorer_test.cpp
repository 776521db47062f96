#include "petri/explorer.h"

#include <cstdint>
#include <string>

#include <gtest/gtest.h>

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

TEST(Explorer, WeightsAndFieldsThatWiden) {
  // A producer adds 3 tokens per firing to `buffer` until `budget` (100)
  // runs out: 101 states, the buffer's field widens from 1 bit to 9.
  NetBuilder b;
  PlaceId budget = b.add_place("budget", 100);
  PlaceId buffer = b.add_place("buffer");
  TransitionId produce = b.add_transition("produce");
  b.add_input(produce, budget);
  b.add_output(produce, buffer, 3);
  ExploreResult r = explore(std::move(b).build());
  EXPECT_EQ(101u, r.states);
  EXPECT_EQ(100u, r.edges);
  EXPECT_EQ(300u, r.max_tokens_in_place);
  EXPECT_EQ(300u, r.place_bounds[buffer]);
  EXPECT_EQ(100u, r.place_bounds[budget]);
  EXPECT_EQ(300u, r.max_tokens_per_marking);
  EXPECT_FALSE(r.one_safe);
  EXPECT_TRUE(r.deadlock);
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

TEST(Explorer, LimitsStopWithAPartialResult) {
  ExploreOptions o;
  o.max_states = 50;
  ExploreResult r = explore(dining_philosophers(6), o);
  EXPECT_FALSE(r.complete);
  EXPECT_EQ(50u, r.states);
  EXPECT_FALSE(r.live.has_value()) << "not decided on a partial graph";
  EXPECT_NE(std::string::npos, r.stopped_why.find("50 states")) << r.stopped_why;

  ExploreOptions m;
  m.max_memory_bytes = 64 * 1024;
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

}  // namespace
}  // namespace strata::petri
