#include "petri/invariants.h"

#include <string>

#include <gtest/gtest.h>

#include "petri/net_families.h"

namespace strata::petri {
namespace {

std::string text(const Net& net, const Semiflow& f) {
  std::string s;
  for (auto [p, w] : f.weights) {
    s += (s.empty() ? "" : " + ") + (w == 1 ? "" : std::to_string(w) + "*") + std::string(net.place_name(p));
  }
  return s + " = " + std::to_string(f.constant);
}

TEST(Invariants, AStateMachineHasOneSemiflowOverAllItsPlaces) {
  NetBuilder b;
  PlaceId p = b.add_place("p", 1);
  PlaceId q = b.add_place("q");
  PlaceId r = b.add_place("r");
  TransitionId t = b.add_transition("t");
  b.add_input(t, p);
  b.add_output(t, q);
  TransitionId u = b.add_transition("u");
  b.add_input(u, q);
  b.add_output(u, r);
  TransitionId v = b.add_transition("v");
  b.add_input(v, r);
  b.add_output(v, p);
  Net net = std::move(b).build();
  Semiflows s = p_semiflows(net);
  ASSERT_TRUE(s.complete);
  ASSERT_EQ(1u, s.flows.size());
  EXPECT_EQ("p + q + r = 1", text(net, s.flows[0]));
  EXPECT_EQ(std::vector<bool>({true, true, true}), s.covered);
}

TEST(Invariants, WeightsAndAnUncoveredPlace) {
  // t: 2a -> b; u: b -> 2a; w: -> c (c is unbounded, no semiflow covers it).
  NetBuilder b;
  PlaceId a = b.add_place("a", 4);
  PlaceId bb = b.add_place("b");
  PlaceId c = b.add_place("c");
  TransitionId t = b.add_transition("t");
  b.add_input(t, a, 2);
  b.add_output(t, bb);
  TransitionId u = b.add_transition("u");
  b.add_input(u, bb);
  b.add_output(u, a, 2);
  TransitionId w = b.add_transition("w");
  b.add_output(w, c);
  Net net = std::move(b).build();
  Semiflows s = p_semiflows(net);
  ASSERT_EQ(1u, s.flows.size());
  EXPECT_EQ("a + 2*b = 4", text(net, s.flows[0]));
  EXPECT_FALSE(s.covered[c]);
  EXPECT_TRUE(is_p_invariant(net, s.flows[0].weights));
  EXPECT_FALSE(is_p_invariant(net, {{a, 1}, {bb, 1}}));
}

TEST(Invariants, EverySemiflowOfTheFamiliesIsAnInvariant) {
  for (const Net& net : {dining_philosophers(4), referendum(4)}) {
    Semiflows s = p_semiflows(net);
    ASSERT_TRUE(s.complete);
    EXPECT_FALSE(s.flows.empty());
    for (const auto& f : s.flows) EXPECT_TRUE(is_p_invariant(net, f.weights)) << text(net, f);
  }
  // Philosophers: each fork with its two users, each philosopher's cycle.
  EXPECT_EQ(8u, p_semiflows(dining_philosophers(4)).flows.size());
}

// Regression: a 10,000-place chain took 3.1 GB (a dense row per place) and
// was reported as having too many semiflows; it has exactly one.
TEST(Invariants, AChainOfTwentyThousandPlacesHasOneSemiflowInLinearMemory) {
  constexpr std::size_t kPlaces = 20'000;
  NetBuilder b;
  std::vector<PlaceId> p;
  for (std::size_t i = 0; i < kPlaces; ++i) p.push_back(b.add_place("p" + std::to_string(i), i == 0 ? 1 : 0));
  for (std::size_t i = 0; i + 1 < kPlaces; ++i) {
    TransitionId t = b.add_transition("t" + std::to_string(i));
    b.add_input(t, p[i], 2);
    b.add_output(t, p[i + 1], 2);
  }
  Net net = std::move(b).build();
  SemiflowLimits limits;
  limits.max_memory_bytes = std::size_t{64} << 20;
  Semiflows s = p_semiflows(net, limits);
  ASSERT_TRUE(s.complete) << s.stopped_why;
  ASSERT_EQ(1u, s.flows.size());
  EXPECT_EQ(kPlaces, s.flows[0].weights.size());
  EXPECT_EQ(1u, s.flows[0].constant);
  EXPECT_TRUE(is_p_invariant(net, s.flows[0].weights));
}

// Contraction, components and the sparse Farkas steps together: two
// separate nets, a chain feeding a fork/join, and a weighted pair.
TEST(Invariants, ChainsForksAndComponentsGiveTheMinimalSemiflows) {
  NetBuilder b;
  PlaceId a = b.add_place("a", 1), c = b.add_place("c"), d = b.add_place("d"), e = b.add_place("e");
  PlaceId f = b.add_place("f"), g = b.add_place("g", 3), h = b.add_place("h");
  TransitionId t1 = b.add_transition("t1");  // a -> c (a step of a chain)
  b.add_input(t1, a);
  b.add_output(t1, c);
  TransitionId t2 = b.add_transition("t2");  // c -> d + e (fork)
  b.add_input(t2, c);
  b.add_output(t2, d);
  b.add_output(t2, e);
  TransitionId t3 = b.add_transition("t3");  // d + e -> f (join)
  b.add_input(t3, d);
  b.add_input(t3, e);
  b.add_output(t3, f);
  TransitionId t4 = b.add_transition("t4");  // f -> a
  b.add_input(t4, f);
  b.add_output(t4, a);
  TransitionId t5 = b.add_transition("t5");  // 3g -> h, another component
  b.add_input(t5, g, 3);
  b.add_output(t5, h);
  Net net = std::move(b).build();
  Semiflows s = p_semiflows(net);
  ASSERT_TRUE(s.complete);
  ASSERT_EQ(3u, s.flows.size());
  EXPECT_EQ("a + c + d + f = 1", text(net, s.flows[0]));
  EXPECT_EQ("a + c + e + f = 1", text(net, s.flows[1]));
  EXPECT_EQ("g + 3*h = 3", text(net, s.flows[2]));
}

TEST(Invariants, StopsAtTheRowLimit) {
  Semiflows s = p_semiflows(dining_philosophers(8), 4);
  EXPECT_FALSE(s.complete);
  EXPECT_EQ("more than 4 rows", s.stopped_why);
  EXPECT_TRUE(s.flows.empty());
}

}  // namespace
}  // namespace strata::petri
