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

namespace strata::petri {
namespace {

namespace fs = std::filesystem;

const fs::path kShared = fs::path(STRATA_SOURCE_DIR) / ".." / "shared" / "pnml";
constexpr std::uint64_t kCiStates = 1'000'000;

struct Answer {
  std::string model;
  std::map<std::string, std::string> values;  // column -> text
  std::uint64_t number(const std::string& column) const { return std::stoull(values.at(column)); }
  bool verdict(const std::string& column) const { return values.at(column) == "TRUE"; }
};

std::vector<Answer> answers() {
  std::vector<Answer> out;
  std::ifstream in(kShared / "answers.csv");
  std::string line;
  std::vector<std::string> header;
  auto split = [](const std::string& s) {
    std::vector<std::string> cells;
    std::stringstream ss(s);
    for (std::string cell; std::getline(ss, cell, ',');) cells.push_back(cell);
    return cells;
  };
  if (!std::getline(in, line)) return out;
  header = split(line);
  while (std::getline(in, line)) {
    auto cells = split(line);
    if (cells.size() != header.size()) continue;
    Answer a{cells[0], {}};
    for (std::size_t i = 0; i < header.size(); ++i) a.values[header[i]] = cells[i];
    out.push_back(std::move(a));
  }
  return out;
}

// The models in answers.csv, read once (none when the folder is absent).
const std::vector<Answer>& all_answers() {
  static const std::vector<Answer> a = fs::exists(kShared / "answers.csv") ? answers() : std::vector<Answer>{};
  return a;
}

std::vector<std::string> model_names() {
  std::vector<std::string> names;
  for (const auto& a : all_answers()) names.push_back(a.model);
  if (names.empty()) names.push_back("absent");  // one test, which skips
  return names;
}

class MccModel : public ::testing::TestWithParam<std::string> {};

TEST_P(MccModel, ExplorerAgreesWithThePublishedAnswers) {
  if (!fs::exists(kShared / "answers.csv")) GTEST_SKIP() << "skipped: ../shared/pnml not present";
  const Answer* a = nullptr;
  for (const auto& x : all_answers()) a = x.model == GetParam() ? &x : a;
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

INSTANTIATE_TEST_SUITE_P(Shared, MccModel, ::testing::ValuesIn(model_names()),
                         [](const ::testing::TestParamInfo<std::string>& p) {
                           std::string name = p.param;
                           for (char& c : name) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
                           return name;
                         });

}  // namespace
}  // namespace strata::petri
