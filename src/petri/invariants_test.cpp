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

TEST(Invariants, StopsAtTheRowLimit) {
  Semiflows s = p_semiflows(dining_philosophers(8), 4);
  EXPECT_FALSE(s.complete);
}

}  // namespace
}  // namespace strata::petri
