#include <random>

#include <fmt/format.h>

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include "petri/dump.h"
#include "petri/state.h"

namespace strata::petri {
namespace {

Net chain() {
  // start -> a -> b, with t_ab needing 2 tokens of a.
  NetBuilder b;
  PlaceId start = b.add_place("start", 2);
  PlaceId a = b.add_place("a");
  PlaceId bb = b.add_place("b");
  TransitionId t1 = b.add_transition("to_a");
  TransitionId t2 = b.add_transition("to_b");
  b.add_input(t1, start);
  b.add_output(t1, a);
  b.add_input(t2, a, 2);
  b.add_output(t2, bb, 3);
  return std::move(b).build();
}

TEST(State, FiresByThePapersStateTransitionFunction) {
  Net net = chain();
  State s(net);
  EXPECT_EQ("start:2", dump_marking(net, s.marking()));
  ASSERT_TRUE(s.is_enabled(0));
  EXPECT_FALSE(s.is_enabled(1));
  ASSERT_TRUE(s.fire(0).ok());
  EXPECT_EQ("start:1 a:1", dump_marking(net, s.marking()));
  EXPECT_FALSE(s.is_enabled(1));
  ASSERT_TRUE(s.fire(0).ok());
  EXPECT_TRUE(s.is_enabled(1));
  EXPECT_FALSE(s.is_enabled(0));
  ASSERT_TRUE(s.fire(1).ok());
  EXPECT_EQ("b:3", dump_marking(net, s.marking()));
  EXPECT_TRUE(s.enabled().empty());
}

TEST(State, AddedMarksEnableReaders) {
  Net net = chain();
  State s(net, {0, 1, 0});
  EXPECT_TRUE(s.enabled().empty());
  ASSERT_TRUE(s.add_tokens(1, 1).ok());
  EXPECT_EQ(std::vector<TransitionId>{1}, s.enabled().sorted());
  s.remove_tokens(1, 1);
  EXPECT_TRUE(s.enabled().empty());
}

TEST(State, FirstEnabledIsHighestPriorityThenDeclarationOrder) {
  NetBuilder b;
  PlaceId p = b.add_place("p", 1);
  b.add_transition("low", 0);
  b.add_transition("high_1", 3);
  b.add_transition("high_2", 3);
  b.add_transition("negative", -1);
  for (TransitionId t = 0; t < 4; ++t) b.add_input(t, p);
  Net net = std::move(b).build();
  State s(net);
  EXPECT_EQ(1u, s.enabled().first());
  EXPECT_EQ((std::vector<TransitionId>{1, 2, 0, 3}), s.enabled().sorted());
}

TEST(State, OverflowFailsAndLeavesTheStateAsItWas) {
  NetBuilder b;
  PlaceId p = b.add_place("p", kMaxTokens);
  TransitionId t = b.add_transition("pump");
  b.add_output(t, p);
  Net net = std::move(b).build();
  State s(net);
  auto r = s.fire(t);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(core::ErrorCode::Overflow, r.error().code);
  EXPECT_EQ(kMaxTokens, s.tokens(p));
  EXPECT_FALSE(s.add_tokens(p, 1).ok());
}

TEST(EnabledSet, WorksAcrossManyLevels) {
  // 70000 transitions: three levels of 64-bit words.
  NetBuilder b;
  std::vector<PlaceId> places;
  for (int i = 0; i < 70000; ++i) places.push_back(b.add_place(fmt::format("p{}", i)));
  for (int i = 0; i < 70000; ++i) {
    TransitionId t = b.add_transition(fmt::format("t{}", i));
    b.add_input(t, places[i]);
  }
  Net net = std::move(b).build();
  State s(net);
  EXPECT_FALSE(s.enabled().first());
  ASSERT_TRUE(s.add_tokens(69999, 1).ok());
  ASSERT_TRUE(s.add_tokens(4097, 1).ok());
  EXPECT_EQ(4097u, s.enabled().first());
  s.remove_tokens(4097, 1);
  EXPECT_EQ(69999u, s.enabled().first());
  EXPECT_EQ(1u, s.enabled().size());
}

// Property: after any sequence of firings and added marks, the incrementally
// kept enabled set equals a full rescan with the paper's rule, and the first
// member is the best-ranked enabled transition.
RC_GTEST_PROP(StateProperty, IncrementalEnabledSetMatchesFullRescan, ()) {
  const auto places = *rc::gen::inRange<std::size_t>(1, 12);
  const auto transitions = *rc::gen::inRange<std::size_t>(1, 16);
  NetBuilder b;
  for (std::size_t p = 0; p < places; ++p) {
    b.add_place(fmt::format("p{}", p), *rc::gen::inRange<Tokens>(0, 4));
  }
  for (std::size_t t = 0; t < transitions; ++t) {
    TransitionId id = b.add_transition(fmt::format("t{}", t), *rc::gen::inRange(-1, 2));
    auto arcs = *rc::gen::inRange<std::size_t>(0, 4);
    for (std::size_t i = 0; i < arcs; ++i) {
      auto p = *rc::gen::inRange<std::size_t>(0, places);
      auto w = *rc::gen::inRange<std::uint32_t>(1, 3);
      if (*rc::gen::arbitrary<bool>())
        b.add_input(id, static_cast<PlaceId>(p), w);
      else
        b.add_output(id, static_cast<PlaceId>(p), w);
    }
  }
  Net net = std::move(b).build();
  State s(net);
  Marking reference = net.initial_marking();
  const auto steps = *rc::gen::inRange(0, 40);
  for (int step = 0; step < steps; ++step) {
    std::vector<TransitionId> expected;
    for (TransitionId t = 0; t < net.transition_count(); ++t) {
      if (is_enabled(net, reference, t)) expected.push_back(t);
    }
    auto got = s.enabled().sorted();
    std::vector<TransitionId> got_by_id(got);
    std::sort(got_by_id.begin(), got_by_id.end());
    RC_ASSERT(got_by_id == expected);
    if (!expected.empty()) {
      TransitionId best = expected[0];
      for (TransitionId t : expected) {
        if (net.priority(t) > net.priority(best)) best = t;
      }
      RC_ASSERT(s.enabled().first() == std::optional<TransitionId>(best));
    }
    if (!expected.empty() && *rc::gen::inRange(0, 4) != 0) {
      TransitionId t = s.enabled().at(*rc::gen::inRange<std::size_t>(0, s.enabled().size()));
      RC_ASSERT(s.fire(t).ok());
      for (const Arc& a : net.inputs(t)) reference[a.node] -= a.weight;
      for (const Arc& a : net.outputs(t)) reference[a.node] += a.weight;
    } else {
      auto p = static_cast<PlaceId>(*rc::gen::inRange<std::size_t>(0, places));
      RC_ASSERT(s.add_tokens(p, 1).ok());
      reference[p] += 1;
    }
    RC_ASSERT(s.marking() == reference);
  }
}

}  // namespace
}  // namespace strata::petri
