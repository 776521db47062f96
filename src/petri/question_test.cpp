// Questions (question.h) against the full exploration: the deadlock verdict
// of explore() and, for EF/AG, every marking of build_reach_graph(), with
// and without stubborn sets, on the generated families, small hand-made
// nets and the corpus in ../shared/pnml (skipped when absent). Every
// witness is replayed.
#include "petri/question.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "petri/explorer.h"
#include "petri/net_families.h"
#include "petri/pnml.h"
#include "petri/reach_graph.h"
#include "petri/structural.h"
#include "petri/question_test_support.h"
#include "petri/test_corpus.h"

namespace strata::petri {
namespace {

namespace fs = std::filesystem;
using testing::ask;
using testing::expect_witness_replays;
using testing::with_reduction;

// ask, with_reduction and expect_witness_replays: question_test_support.h.

// k tokens going round a ring of n places: never deadlocks; C(n+k-1, k) markings.
Net ring(unsigned n, Tokens k) {
  NetBuilder b;
  std::vector<PlaceId> p;
  for (unsigned i = 0; i < n; ++i) p.push_back(b.add_place("r" + std::to_string(i), i == 0 ? k : 0));
  for (unsigned i = 0; i < n; ++i) {
    TransitionId t = b.add_transition("step" + std::to_string(i));
    b.add_input(t, p[i]);
    b.add_output(t, p[(i + 1) % n]);
  }
  return std::move(b).build();
}

// A random predicate over the net's places (constants up to max_const).
std::string random_predicate(std::mt19937& rng, const Net& net, int depth, Tokens max_const) {
  std::uniform_int_distribution<int> pick(0, 9);
  const int k = pick(rng);
  if (depth > 0 && k < 2)
    return "(" + random_predicate(rng, net, depth - 1, max_const) + " && " +
           random_predicate(rng, net, depth - 1, max_const) + ")";
  if (depth > 0 && k < 4)
    return "(" + random_predicate(rng, net, depth - 1, max_const) + " || " +
           random_predicate(rng, net, depth - 1, max_const) + ")";
  if (depth > 0 && k < 5) return "!" + random_predicate(rng, net, depth - 1, max_const);
  static const char* kOps[] = {"==", "!=", "<", "<=", ">", ">="};
  std::uniform_int_distribution<std::size_t> place(0, net.place_count() - 1);
  std::uniform_int_distribution<int> op(0, 5);
  std::uniform_int_distribution<Tokens> constant(0, max_const);
  std::string lhs(net.place_name(static_cast<PlaceId>(place(rng))));
  std::string rhs =
      pick(rng) < 2 ? std::string(net.place_name(static_cast<PlaceId>(place(rng)))) : std::to_string(constant(rng));
  return "\"" + lhs + "\" " + kOps[op(rng)] + " " + (rhs[0] >= '0' && rhs[0] <= '9' ? rhs : "\"" + rhs + "\"");
}

// EF and AG of `count` random predicates against every reachable marking.
void check_random_predicates(const Net& net, unsigned seed, int count) {
  const ReachGraph g = build_reach_graph(net);
  ASSERT_TRUE(g.complete());
  std::mt19937 rng(seed);
  for (int i = 0; i < count; ++i) {
    const std::string pred = random_predicate(rng, net, 3, 2);
    for (const char* kind : {"EF ", "AG "}) {
      const Question q = ask(net, kind + pred);
      bool any = false;
      for (StateId s = 0; s < g.state_count() && !any; ++s) any = q.target.holds(g.marking(s));
      const Answer expected = (q.kind == QuestionKind::Reachable) == any ? Answer::Yes : Answer::No;
      for (bool reduce : {true, false}) {
        for (bool structural : {true, false}) {
          const QuestionResult r = answer_question(net, q, with_reduction(reduce, structural));
          ASSERT_EQ(expected, r.answer) << kind << pred << (reduce ? " (reduced)" : " (full)")
                                        << (structural ? "" : " (no structure)");
          if (any && r.structural_reason.empty()) expect_witness_replays(net, q, r);
          if (!reduce) {
            EXPECT_LE(r.states, g.state_count());
          }
        }
      }
    }
  }
}

TEST(QuestionDeadlock, FamiliesAgreeWithTheFullExploration) {
  for (unsigned n = 2; n <= 7; ++n) {
    for (const Net& net : {dining_philosophers(n), referendum(n)}) {
      const ExploreResult full = explore(net);
      const Question q = ask(net, "deadlock");
      for (bool reduce : {true, false}) {
        const QuestionResult r = answer_question(net, q, with_reduction(reduce));
        EXPECT_EQ(full.deadlock ? Answer::Yes : Answer::No, r.answer) << n;
        EXPECT_LE(r.states, full.states);
        if (r.answer == Answer::Yes) expect_witness_replays(net, q, r);
      }
    }
  }
}

TEST(QuestionDeadlock, ReductionVisitsFewerMarkingsOnReferendum) {
  const Net net = referendum(10);  // 59 050 markings
  const QuestionResult reduced = answer_question(net, ask(net, "deadlock"), with_reduction(true));
  EXPECT_EQ(Answer::Yes, reduced.answer);
  EXPECT_LE(reduced.states, 12u);  // one interleaving: start, then each voter once
}

TEST(QuestionDeadlock, DeadlockFreeRingIsSearchedWhole) {
  const Net net = ring(5, 3);  // C(7, 3) = 35 markings
  for (bool reduce : {true, false}) {
    const QuestionResult r = answer_question(net, ask(net, "deadlock"), with_reduction(reduce));
    EXPECT_EQ(Answer::No, r.answer);
    EXPECT_FALSE(r.has_witness);
    if (!reduce) {
      EXPECT_EQ(35u, r.states);
    }
  }
}

TEST(QuestionDeadlock, TransitionWithoutInputsSettlesItStructurally) {
  NetBuilder b;
  PlaceId p = b.add_place("p", 0);
  TransitionId source = b.add_transition("source");
  b.add_output(source, p);
  const Net net = std::move(b).build();
  const QuestionResult r = answer_question(net, ask(net, "deadlock"));
  EXPECT_EQ(Answer::No, r.answer);
  EXPECT_EQ(0u, r.states);
  EXPECT_EQ("transition 'source' has no input place: it is enabled in every marking", r.structural_reason);
}

TEST(QuestionDeadlock, InitialDeadlockHasAnEmptyWitness) {
  NetBuilder b;
  PlaceId p = b.add_place("p", 0);
  TransitionId t = b.add_transition("t");
  b.add_input(t, p);
  const Net net = std::move(b).build();
  const QuestionResult r = answer_question(net, ask(net, "deadlock"));
  EXPECT_EQ(Answer::Yes, r.answer);
  EXPECT_TRUE(r.has_witness);
  EXPECT_TRUE(r.witness.empty());
}

// A small random net: arcs of weight 1 or 2, some of them tests (pre =
// post), a few tokens.
Net random_net(std::mt19937& rng) {
  NetBuilder b;
  std::uniform_int_distribution<int> places(3, 7), transitions(3, 8), tokens(0, 2), pick(0, 99);
  std::vector<PlaceId> p;
  const int np = places(rng);
  p.reserve(static_cast<std::size_t>(np));
  for (int i = 0; i < np; ++i) p.push_back(b.add_place("p" + std::to_string(i), static_cast<Tokens>(tokens(rng))));
  std::uniform_int_distribution<std::size_t> place(0, p.size() - 1);
  const int nt = transitions(rng);
  for (int i = 0; i < nt; ++i) {
    TransitionId t = b.add_transition("t" + std::to_string(i));
    std::vector<char> in(p.size(), 0), out(p.size(), 0);
    for (int k = 0, arcs = 1 + pick(rng) % 3; k < arcs; ++k) in[place(rng)] = 1;
    for (int k = 0, arcs = pick(rng) % 3; k < arcs; ++k) out[place(rng)] = 1;
    for (std::size_t k = 0; k < p.size(); ++k) {
      const std::uint32_t w = pick(rng) < 20 ? 2 : 1;
      if (in[k]) b.add_input(t, p[k], w);
      if (out[k] || (in[k] && pick(rng) < 25)) b.add_output(t, p[k], in[k] && !out[k] ? w : 1);
    }
  }
  return std::move(b).build();
}

TEST(QuestionDeadlock, RandomNetsAgreeWithTheFullExploration) {
  std::mt19937 rng(19);
  int decided = 0;
  for (int i = 0; i < 400; ++i) {
    const Net net = random_net(rng);
    ExploreOptions eo;
    eo.max_states = 3000;
    eo.liveness = false;
    const ExploreResult full = explore(net, eo);
    if (!full.complete) continue;
    ++decided;
    const Question q = ask(net, "deadlock");
    for (bool structural : {true, false}) {
      const QuestionResult r = answer_question(net, q, with_reduction(true, structural));
      ASSERT_EQ(full.deadlock ? Answer::Yes : Answer::No, r.answer) << "net " << i;
      if (r.answer == Answer::Yes && r.structural_reason.empty()) expect_witness_replays(net, q, r);
    }
    if (full.states <= 300 && i % 4 == 0) check_random_predicates(net, static_cast<unsigned>(i), 4);
  }
  EXPECT_GT(decided, 200);
}

// Without reduction, a deadlock-free net is searched whole: every marking
// stored once and every edge fired once, those to a marking already stored
// too (the search looks them up from the packed marking, in a batch,
// without firing them). The rings of 300 tokens widen the store's fields
// as they go (a successor that would not fit is fired, not looked up).
TEST(QuestionDeadlock, SuccessorsAlreadyStoredCountAsFiredEdges) {
  std::mt19937 rng(41);
  std::vector<Net> nets;
  nets.push_back(ring(5, 3));
  nets.push_back(ring(3, 300));
  for (int i = 0; i < 200; ++i) nets.push_back(random_net(rng));
  int compared = 0;
  for (std::size_t i = 0; i < nets.size(); ++i) {
    const Net& net = nets[i];
    ExploreOptions eo;
    eo.max_states = 3000;
    eo.liveness = false;
    const ExploreResult full = explore(net, eo);
    if (!full.complete || full.deadlock) continue;
    const QuestionResult r = answer_question(net, ask(net, "deadlock"), with_reduction(false, false));
    ASSERT_EQ(Answer::No, r.answer) << "net " << i;
    EXPECT_EQ(full.states, r.states) << "net " << i;
    EXPECT_EQ(full.edges, r.edges) << "net " << i;
    ++compared;
  }
  EXPECT_GT(compared, 10);
}

TEST(QuestionReach, RandomPredicatesOnFamiliesAgreeWithEveryMarking) {
  check_random_predicates(dining_philosophers(4), 1, 40);
  check_random_predicates(referendum(5), 2, 40);
  check_random_predicates(ring(4, 3), 3, 40);
}

TEST(QuestionReach, PSemiflowBoundSettlesItStructurally) {
  const Net net = dining_philosophers(3);  // Think_i + Catch1_i + Catch2_i + Eat_i = 1
  const QuestionResult r = answer_question(net, ask(net, "EF Eat_1 >= 2"));
  EXPECT_EQ(Answer::No, r.answer);
  EXPECT_EQ(0u, r.states);
  EXPECT_NE(std::string::npos, r.structural_reason.find("Eat_1 in [0, 1]")) << r.structural_reason;
  const QuestionResult ag = answer_question(net, ask(net, "AG Eat_1 <= 1 && Fork_2 < 2"));
  EXPECT_EQ(Answer::Yes, ag.answer);
  EXPECT_FALSE(ag.structural_reason.empty());
  const QuestionResult searched = answer_question(net, ask(net, "EF Eat_1 >= 2"), with_reduction(true, false));
  EXPECT_EQ(Answer::No, searched.answer);
  EXPECT_GT(searched.states, 0u);
}

TEST(QuestionReach, AgFailsWithACounterexample) {
  const Net net = dining_philosophers(3);
  const Question q = ask(net, "AG !(Eat_1 == 1 && Eat_3 == 0)");
  const QuestionResult r = answer_question(net, q);
  EXPECT_EQ(Answer::No, r.answer);
  expect_witness_replays(net, q, r);
  EXPECT_EQ(1u, r.witness_marking[net.find_place("Eat_1").value()]);
}

TEST(QuestionLimits, MaxStatesGivesNotDecided) {
  const Net net = ring(8, 6);  // 1716 markings, no deadlock
  QuestionOptions o = with_reduction(false);
  o.max_states = 100;
  const QuestionResult r = answer_question(net, ask(net, "deadlock"), o);
  EXPECT_EQ(Answer::NotDecided, r.answer);
  EXPECT_EQ(100u, r.states);
  EXPECT_EQ("stopped at 100 markings (the limit)", r.stopped_why);
}

TEST(QuestionLimits, APassedDeadlineGivesNotDecided) {
  const Net net = ring(3, 300);  // 45 451 markings: the deadline is checked every 4,096
  QuestionOptions o = with_reduction(false);
  o.deadline = std::chrono::steady_clock::now();
  const QuestionResult r = answer_question(net, ask(net, "EF r2 == 301"), [&] {
    QuestionOptions copy = o;
    copy.structural = false;
    return copy;
  }());
  EXPECT_EQ(Answer::NotDecided, r.answer);
  EXPECT_FALSE(r.has_witness);
  EXPECT_EQ("the time limit was reached after 4096 markings", r.stopped_why);
}

TEST(QuestionLimits, ProgressCanInterrupt) {
  const Net net = ring(8, 6);
  QuestionOptions o = with_reduction(false);
  o.progress_every = 10;
  int calls = 0;
  o.progress = [&](const ExploreProgress&) { return ++calls < 3; };
  const QuestionResult r = answer_question(net, ask(net, "EF r0 == 100"), [&] {
    QuestionOptions copy = o;
    copy.structural = false;
    return copy;
  }());
  EXPECT_EQ(Answer::NotDecided, r.answer);
  EXPECT_EQ(3, calls);
  EXPECT_EQ("interrupted after 30 markings", r.stopped_why);
}

TEST(QuestionLimits, MoreThan255TokensWidenTheStore) {
  const Net net = ring(3, 300);  // C(302, 2) = 45 451 markings
  const QuestionResult r = answer_question(net, ask(net, "EF r2 == 300 && r0 == 0"), with_reduction(false, false));
  EXPECT_EQ(Answer::Yes, r.answer);
  const QuestionResult none = answer_question(net, ask(net, "EF r2 == 301"), with_reduction(false, false));
  EXPECT_EQ(Answer::No, none.answer);
  EXPECT_EQ(45451u, none.states);
}

TEST(Replay, ReportsTheFirstTransitionNotEnabled) {
  const Net net = ring(3, 1);
  auto seq = parse_sequence("step0 step1, step1", net);
  ASSERT_TRUE(seq.ok());
  const ReplayResult r = replay(net, seq.value());
  EXPECT_FALSE(r.complete);
  EXPECT_EQ(2u, r.fired);
  EXPECT_EQ("step 3: 'step1' is not enabled (r1 has 0 of 1)", r.error);
  EXPECT_EQ((Marking{0, 0, 1}), r.marking);
}

TEST(Replay, SequenceErrorsGiveLineAndColumn) {
  const Net net = ring(3, 1);
  auto one = parse_sequence("step0  stepX", net);
  ASSERT_FALSE(one.ok());
  EXPECT_EQ("column 8: no transition 'stepX'", one.error().text());
  EXPECT_EQ(0u, one.error().line);
  EXPECT_EQ(8u, one.error().column);
  EXPECT_EQ("no transition 'stepX'", one.error().message);
  auto lines = parse_sequence("# a witness\nstep0\n  step9 # last\n", net);
  ASSERT_FALSE(lines.ok());
  EXPECT_EQ("line 3, column 3: no transition 'step9'", lines.error().text());
  auto empty = parse_sequence(" # nothing\n", net);
  ASSERT_TRUE(empty.ok());
  EXPECT_TRUE(empty.value().empty());
}

// ---- the corpus -------------------------------------------------------------

struct CorpusNet {
  std::string model;
  std::uint64_t states = 0;
  bool deadlock = false;
};

class CorpusQuestion : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    if (!corpus::corpus_present()) GTEST_SKIP() << "skipped: ../shared/pnml not present";
    const corpus::CorpusAnswer* a = corpus::corpus_answer(GetParam());
    ASSERT_NE(nullptr, a) << GetParam();
    answer_ = {a->model, a->number("states"), a->verdict("deadlock")};
    auto loaded = read_pnml(a->pnml().string());
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    net_ = std::move(loaded).value().net;
  }
  CorpusNet answer_;
  Net net_;
};

constexpr std::uint64_t kCorpusFullStates = 100'000;         // compared with explore() up to this
constexpr std::uint64_t kCorpusUnreducedStates = 1'000'000;  // searched without reduction up to this

TEST_P(CorpusQuestion, DeadlockAgreesWithAnswersAndFullExploration) {
  const Question q = ask(net_, "deadlock");
  if (answer_.states <= kCorpusFullStates) {
    const ExploreResult full = explore(net_, [] {
      ExploreOptions o;
      o.liveness = false;
      return o;
    }());
    ASSERT_TRUE(full.complete);
    EXPECT_EQ(answer_.deadlock, full.deadlock);
  }
  for (bool reduce : {true, false}) {
    if (!reduce && answer_.states > kCorpusUnreducedStates) continue;  // every marking: minutes in a debug build
    const QuestionResult r = answer_question(net_, q, with_reduction(reduce));
    ASSERT_NE(Answer::NotDecided, r.answer) << r.stopped_why;
    EXPECT_EQ(answer_.deadlock ? Answer::Yes : Answer::No, r.answer) << (reduce ? "reduced" : "full");
    EXPECT_LE(r.states, answer_.states);
    if (r.answer == Answer::Yes) expect_witness_replays(net_, q, r);
  }
}

TEST_P(CorpusQuestion, RandomPredicatesAgreeWithEveryMarking) {
  if (answer_.states > 20'000) GTEST_SKIP() << "skipped: " << answer_.states << " markings kept whole";
  check_random_predicates(net_, 7, 12);
}

INSTANTIATE_TEST_SUITE_P(Shared, CorpusQuestion, ::testing::ValuesIn(corpus::corpus_model_names()),
                         corpus::corpus_test_name);

}  // namespace
}  // namespace strata::petri
