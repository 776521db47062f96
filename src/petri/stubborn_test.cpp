// How much the stubborn sets prune in the deadlock question (stubborn.h):
// the markings the search visits, on the dining philosophers built in code
// and on the corpus against LoLA 2.0's counts (lola-deadlock.csv beside
// answers.csv; skipped when the corpus is absent). Whether the answers are
// right is question_test.cpp's and pnml_answers_test.cpp's.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "petri/net_families.h"
#include "petri/pnml.h"
#include "petri/question.h"
#include "petri/question_test_support.h"
#include "petri/test_corpus.h"

namespace strata::petri {
namespace {

using testing::ask;
using testing::expect_witness_replays;

// n philosophers, each taking either fork first (net_families.h: each
// philosopher's five transitions in turn). The search fires a set's
// transitions in declaration order, so how soon it meets the deadlock
// (every philosopher holding one fork) depends on it: n + 1 markings in
// the MCC's order (the corpus nets), 2n here, where a philosopher with a
// fork eats before the next takes one. One closure per key visited 37 for
// 12 philosophers.
TEST(StubbornSets, PhilosophersReachTheirDeadlockInFewMarkings) {
  for (unsigned n : {5u, 12u}) {
    const Net net = dining_philosophers(n);
    const Question q = ask(net, "deadlock");
    const QuestionResult r = answer_question(net, q);
    ASSERT_EQ(Answer::Yes, r.answer) << n;
    EXPECT_EQ(2 * n, r.states) << n << " philosophers";
    expect_witness_replays(net, q, r);
  }
}

// LoLA 2.0's markings visited for the deadlock question, by model.
std::map<std::string, std::uint64_t> lola_markings() {
  std::map<std::string, std::uint64_t> out;
  std::ifstream in(corpus::kCorpusDir / "lola-deadlock.csv");
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  {
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) header.push_back(cell);
  }
  std::size_t column = 0;
  while (column < header.size() && header[column] != "lola_markings_visited") ++column;
  while (std::getline(in, line)) {
    std::vector<std::string> c;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) c.push_back(cell);
    if (column < c.size()) out[c[0]] = std::stoull(c[column]);
  }
  return out;
}

TEST(StubbornSets, VisitsNoMoreMarkingsThanLolaOnTheCorpus) {
  if (!corpus::corpus_present()) GTEST_SKIP() << "skipped: ../shared/pnml not present";
  const auto lola = lola_markings();
  if (lola.empty()) GTEST_SKIP() << "skipped: ../shared/pnml/lola-deadlock.csv not present";
  std::size_t compared = 0;
  for (const auto& [model, lola_count] : lola) {
    auto loaded = read_pnml((corpus::kCorpusDir / model / "model.pnml").string());
    ASSERT_TRUE(loaded.ok()) << model;
    const Net& net = loaded.value().net;
    const QuestionResult r = answer_question(net, ask(net, "deadlock"));
    ASSERT_NE(Answer::NotDecided, r.answer) << model;
    EXPECT_EQ(corpus::corpus_answer(model)->verdict("deadlock") ? Answer::Yes : Answer::No, r.answer) << model;
    EXPECT_LE(r.states, lola_count) << model << ": LoLA 2.0 visits " << lola_count;
    ++compared;
  }
  EXPECT_EQ(23u, compared);
}

}  // namespace
}  // namespace strata::petri
