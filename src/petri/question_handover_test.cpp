// The depth-first search where the stubborn sets prune nothing: it decides
// the deadlock question itself (it once handed it over to the full
// explorer), in the explorer's packed storage (packed_markings.h), within
// the memory the explorer takes for the same markings; a place only tested
// is no conflict. Every answer is the full exploration's.
#include <gtest/gtest.h>

#include <string>

#include "petri/explorer.h"
#include "petri/net_families.h"
#include "petri/question.h"
#include "petri/question_test_support.h"

namespace strata::petri {
namespace {

using testing::ask;
using testing::expect_witness_replays;
using testing::with_reduction;

// n counters filled k times each, every fill taking a token from one shared
// pool (n * k tokens): every enabled transition can disable every other, so
// stubborn sets prune nothing; (k+1)^n markings, one deadlock (all full).
Net pooled_counters(unsigned n, Tokens k) {
  NetBuilder b;
  PlaceId pool = b.add_place("pool", n * k);
  for (unsigned i = 0; i < n; ++i) {
    PlaceId budget = b.add_place("budget" + std::to_string(i), k);
    PlaceId count = b.add_place("count" + std::to_string(i), 0);
    TransitionId t = b.add_transition("inc" + std::to_string(i));
    b.add_input(t, pool);
    b.add_input(t, budget);
    b.add_output(t, count);
  }
  return std::move(b).build();
}

// k tokens going round a ring of n places, each step through a lock: taken
// by step_i (r_i -> held_i), given back by pass_i (held_i -> r_{i+1}); the
// steps compete for it, so stubborn sets prune nothing. With
// `read_lock`, each step only tests the lock (pre = post = 1) and goes
// straight to r_{i+1}: no step can disable another.
Net locked_ring(unsigned n, Tokens k, bool read_lock) {
  NetBuilder b;
  PlaceId lock = b.add_place("lock", 1);
  std::vector<PlaceId> p;
  for (unsigned i = 0; i < n; ++i) p.push_back(b.add_place("r" + std::to_string(i), i == 0 ? k : 0));
  for (unsigned i = 0; i < n; ++i) {
    TransitionId t = b.add_transition("step" + std::to_string(i));
    b.add_input(t, lock);
    b.add_input(t, p[i]);
    if (read_lock) {
      b.add_output(t, lock);
      b.add_output(t, p[(i + 1) % n]);
      continue;
    }
    PlaceId held = b.add_place("held" + std::to_string(i), 0);
    b.add_output(t, held);
    TransitionId pass = b.add_transition("pass" + std::to_string(i));
    b.add_input(pass, held);
    b.add_output(pass, lock);
    b.add_output(pass, p[(i + 1) % n]);
  }
  return std::move(b).build();
}

TEST(QuestionDeadlock, WhenStubbornSetsPruneNothingTheSearchDecidesInPackedStorage) {
  const Net with_deadlock = pooled_counters(4, 4);  // 625 markings
  const Question q = ask(with_deadlock, "deadlock");
  const QuestionResult r = answer_question(with_deadlock, q);
  EXPECT_EQ(Answer::Yes, r.answer);
  expect_witness_replays(with_deadlock, q, r);
  // A lock around a ring: no deadlock, every marking searched, no more
  // memory than the explorer's table and queue for them.
  const Net free = locked_ring(7, 5, false);
  const ExploreResult all = explore(free);
  const QuestionResult full = answer_question(free, ask(free, "deadlock"));
  EXPECT_EQ(Answer::No, full.answer);
  EXPECT_EQ(all.states, full.states);
  EXPECT_LE(full.memory_bytes, all.memory_bytes);
  QuestionOptions limited;
  limited.max_states = all.states - 1;  // the search stops one short
  const QuestionResult stopped = answer_question(free, ask(free, "deadlock"), limited);
  EXPECT_EQ(Answer::NotDecided, stopped.answer);
  EXPECT_EQ(all.states - 1, stopped.states);
}

// n processes, each idle or busy, all through one pool of n + 1 tokens:
// take_i (idle_i + pool -> busy_i) and give_i (busy_i + pool -> idle_i + 2
// pool). Every transition takes from the pool, so each can disable the
// others and a stubborn set holds every enabled one; 2^n markings, no
// deadlock.
Net shared_pool(unsigned n) {
  NetBuilder b;
  PlaceId pool = b.add_place("pool", n + 1);
  for (unsigned i = 0; i < n; ++i) {
    PlaceId idle = b.add_place("idle" + std::to_string(i), 1);
    PlaceId busy = b.add_place("busy" + std::to_string(i), 0);
    TransitionId take = b.add_transition("take" + std::to_string(i));
    b.add_input(take, idle);
    b.add_input(take, pool);
    b.add_output(take, busy);
    TransitionId give = b.add_transition("give" + std::to_string(i));
    b.add_input(give, busy);
    b.add_input(give, pool);
    b.add_output(give, idle);
    b.add_output(give, pool, 2);
  }
  return std::move(b).build();
}

TEST(QuestionDeadlock, WideSetsThatPruneNothingAreSearchedWhole) {
  // Ten enabled transitions at every marking, none pruned: the search
  // visits every marking itself, in no more memory than the explorer.
  const Net net = shared_pool(10);
  const ExploreResult all = explore(net);
  ASSERT_EQ(1024u, all.states);
  const QuestionResult r = answer_question(net, ask(net, "deadlock"));
  EXPECT_EQ(Answer::No, r.answer);
  EXPECT_EQ(all.states, r.states);
  EXPECT_LE(r.memory_bytes, all.memory_bytes);
  // Where the sets prune, fewer: Referendum's voters are independent.
  const Net votes = referendum(8);
  const QuestionResult v = answer_question(votes, ask(votes, "deadlock"));
  EXPECT_EQ(Answer::Yes, v.answer);
  EXPECT_LT(v.states, explore(votes).states);
}

// A place no P-semiflow covers starts in a field as wide as its initial
// tokens: 300 firings into it widen the field four times (1 to 16 bits),
// re-packing every stored marking, as in the explorer.
TEST(QuestionDeadlock, AFieldThatOverflowsIsWidened) {
  NetBuilder b;
  PlaceId budget = b.add_place("budget", 300);
  PlaceId heap = b.add_place("heap", 0);
  TransitionId one = b.add_transition("one");
  b.add_input(one, budget);
  b.add_output(one, heap);
  TransitionId two = b.add_transition("two");  // with `one`, no P-semiflow covers heap
  b.add_input(two, budget);
  b.add_output(two, heap, 2);
  const Net net = std::move(b).build();
  const Question q = ask(net, "deadlock");
  const QuestionResult r = answer_question(net, q, with_reduction(false));
  EXPECT_EQ(Answer::Yes, r.answer);
  EXPECT_EQ(301u, r.states);  // `one` first, 300 times
  ASSERT_TRUE(r.has_witness);
  EXPECT_EQ(300u, r.witness_marking[heap]);
  expect_witness_replays(net, q, r);
  // Every marking, (k1, k2) with k1 + k2 <= 300: C(302, 2).
  const QuestionResult all = answer_question(net, ask(net, "EF heap == 601"), with_reduction(false, false));
  EXPECT_EQ(Answer::No, all.answer);
  EXPECT_EQ(45451u, all.states);
}

TEST(QuestionDeadlock, ASearchDivingToADeadlockIsNotHandedOver) {
  // 70 counters on one pool: sets of 70 enabled transitions prune nothing,
  // but every firing reaches a new marking and the 281st is the deadlock.
  // Handed over to the explorer after 256 markings (as it once was), it
  // would have faced 5^70 markings.
  const Net net = pooled_counters(70, 4);
  QuestionOptions o;
  o.max_states = 10'000;
  const Question q = ask(net, "deadlock");
  const QuestionResult r = answer_question(net, q, o);
  EXPECT_EQ(Answer::Yes, r.answer);
  EXPECT_EQ(281u, r.states);
  expect_witness_replays(net, q, r);
}

TEST(QuestionDeadlock, APlaceOnlyTestedIsNoConflict) {
  // The steps only read the lock: each stubborn set is one step, and the
  // search follows one interleaving instead of all C(11, 5) = 462 markings.
  const Net net = locked_ring(7, 5, true);
  const QuestionResult r = answer_question(net, ask(net, "deadlock"));
  EXPECT_EQ(Answer::No, r.answer);
  EXPECT_LT(r.states, 100u);
  EXPECT_EQ(462u, explore(net).states);
}

}  // namespace
}  // namespace strata::petri
