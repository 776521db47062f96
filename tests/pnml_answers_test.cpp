// The explorer against the Model Checking Contest's published answers for
// the 23 nets in ../shared/pnml (answers.csv, described in ANSWERS.md):
// states, edges, both token maxima and the global verdicts, for every net
// up to 10^6 states; the three larger ones too when STRATA_LONG_TESTS=1.
// Each net's listed P-semiflows are checked by property (y.C = 0 and
// y.M0 = the listed constant) on the imported net. The folder is not part
// of the project: without it every test says so and skips.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "petri/explorer.h"
#include "petri/pnml.h"
#include "petri/test_corpus.h"

namespace strata::petri {
namespace {

namespace fs = std::filesystem;

const fs::path& kShared = corpus::kCorpusDir;
constexpr std::uint64_t kCiStates = 1'000'000;

using corpus::CorpusAnswer;

class MccModel : public ::testing::TestWithParam<std::string> {};

TEST_P(MccModel, ExplorerAgreesWithThePublishedAnswers) {
  if (!fs::exists(kShared / "answers.csv")) GTEST_SKIP() << "skipped: ../shared/pnml not present";
  const CorpusAnswer* a = corpus::corpus_answer(GetParam());
  ASSERT_NE(nullptr, a);
  const char* long_tests = std::getenv("STRATA_LONG_TESTS");
  if (a->number("states") > kCiStates && !(long_tests && std::string(long_tests) == "1")) {
    GTEST_SKIP() << "skipped: " << a->number("states") << " states; run with STRATA_LONG_TESTS=1";
  }
  auto net = read_pnml((kShared / a->model / "model.pnml").string());
  ASSERT_TRUE(net.ok()) << net.error().message;
  ExploreResult r = explore(net.value().net);
  ASSERT_TRUE(r.complete) << r.stopped_why;
  EXPECT_EQ(a->number("states"), r.states);
  EXPECT_EQ(a->number("edges"), r.edges);
  EXPECT_EQ(a->number("max_tokens_in_place"), r.max_tokens_in_place);
  EXPECT_EQ(a->number("max_tokens_per_marking"), r.max_tokens_per_marking);
  EXPECT_EQ(a->verdict("deadlock"), r.deadlock);
  EXPECT_EQ(a->verdict("one_safe"), r.one_safe);
  EXPECT_EQ(a->verdict("quasi_live"), r.quasi_live);
  ASSERT_TRUE(r.live.has_value());
  EXPECT_EQ(a->verdict("live"), *r.live);
}

// "inv : a + 2*b + c = 3": y.C = 0 on the imported net, and y.M0 = 3.
TEST_P(MccModel, ListedPSemiflowsAreInvariantsOfTheImportedNet) {
  if (!fs::exists(kShared / "answers.csv")) GTEST_SKIP() << "skipped: ../shared/pnml not present";
  const fs::path file = kShared / GetParam() / "invariants" / "P-semiflows.txt";
  if (!fs::exists(file)) GTEST_SKIP() << "no P-semiflows listed for " << GetParam();
  auto loaded = read_pnml((kShared / GetParam() / "model.pnml").string());
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  const Net& net = loaded.value().net;
  std::ifstream in(file);
  std::size_t checked = 0;
  for (std::string line; std::getline(in, line);) {
    if (!line.starts_with("inv :")) continue;
    const auto eq = line.rfind('=');
    ASSERT_NE(std::string::npos, eq) << line;
    std::vector<std::pair<PlaceId, std::int64_t>> y;
    std::stringstream terms(line.substr(5, eq - 5));
    for (std::string term; std::getline(terms, term, '+');) {
      term.erase(0, term.find_first_not_of(' '));
      term.erase(term.find_last_not_of(' ') + 1);
      std::int64_t coefficient = 1;
      if (auto star = term.find('*'); star != std::string::npos) {
        coefficient = std::stoll(term.substr(0, star));
        term = term.substr(star + 1);
      }
      auto p = net.find_place(term);
      ASSERT_TRUE(p.has_value()) << "no place '" << term << "' in " << GetParam();
      y.emplace_back(*p, coefficient);
    }
    for (TransitionId t = 0; t < net.transition_count(); ++t) {
      std::int64_t sum = 0;
      for (const auto& [p, c] : y) sum += c * net.incidence(p, t);
      ASSERT_EQ(0, sum) << line << ": y.C is not 0 at transition " << net.transition_name(t);
    }
    std::int64_t initial = 0;
    for (const auto& [p, c] : y) initial += c * static_cast<std::int64_t>(net.initial_marking()[p]);
    EXPECT_EQ(std::stoll(line.substr(eq + 1)), initial) << line;
    ++checked;
  }
  EXPECT_GT(checked, 0u);
}

INSTANTIATE_TEST_SUITE_P(Shared, MccModel, ::testing::ValuesIn(corpus::corpus_model_names()), corpus::corpus_test_name);

}  // namespace
}  // namespace strata::petri
