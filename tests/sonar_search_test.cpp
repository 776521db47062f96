// The sonar search (missions/sonar_search, issue 8) in every shipped
// scenario: the CORAL net and the PROLOG rules make the same primitive calls
// in the same order (what `strata compare` checks), and the search ends as
// the scenario says — the target found from the heading that can see it,
// the time-out, the leak.
#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cli/mission_run.h"
#include "cli/trace_compare.h"

namespace strata::cli {
namespace {

using strategic::Outcome;

const std::string kDir = std::string(STRATA_SOURCE_DIR) + "/missions/sonar_search";

struct SearchRun {
  RunReport report;
  std::string out, err;
  std::vector<TraceRow> rows;
};

SearchRun run(const std::string& mission, const std::string& scenario) {
  RunOptions o;
  o.mission = kDir + "/" + mission;
  o.scenario = scenario;
  o.trace = true;
  std::ostringstream out, err;
  SearchRun r;
  r.report = run_mission(o, out, err);
  r.out = out.str();
  r.err = err.str();
  r.rows = trace_rows(r.report.trace);
  return r;
}

struct Expected {
  std::string scenario;
  Outcome outcome;
  std::vector<std::string> coral_phases, rules_phases;
  std::string report;  // a REPORT the search makes
};

void PrintTo(const Expected& e, std::ostream* os) { *os << e.scenario; }

class SonarSearch : public ::testing::TestWithParam<Expected> {};

// The index of the first row whose call is `call`, or rows.size().
std::size_t find_call(const std::vector<TraceRow>& rows, const std::string& call, std::size_t from = 0) {
  for (std::size_t i = from; i < rows.size(); ++i) {
    if (rows[i].call == call) return i;
  }
  return rows.size();
}

TEST_P(SonarSearch, CoralAndPrologMakeTheSameCallsAndEndAsTheScenarioSays) {
  const Expected& e = GetParam();
  SearchRun coral = run("sonar_search.coral", e.scenario);
  SearchRun rules = run("sonar_search.pl", e.scenario);
  ASSERT_TRUE(coral.report.result.has_value()) << coral.err;
  ASSERT_TRUE(rules.report.result.has_value()) << rules.err;
  EXPECT_EQ("", rules.err) << "the rules load without a warning";
  EXPECT_EQ(std::nullopt, first_difference(coral.rows, rules.rows))
      << side_by_side(coral.rows, rules.rows, {"CORAL", "PROLOG", std::size_t{5}});
  EXPECT_EQ(e.outcome, coral.report.result->outcome) << coral.out;
  EXPECT_EQ(e.outcome, rules.report.result->outcome) << rules.out;
  // CORAL names its phases by their nets, PROLOG by their numbers.
  EXPECT_EQ(e.coral_phases, coral.report.phases) << coral.out;
  EXPECT_EQ(e.rules_phases, rules.report.phases) << rules.out;
  EXPECT_NE(coral.rows.size(), find_call(coral.rows, "report \"" + e.report + "\"")) << coral.out;
  // The sonar was started and stopped, and the vehicle is at the surface.
  const std::size_t on = find_call(coral.rows, "exec start_sonar");
  ASSERT_NE(coral.rows.size(), on);
  EXPECT_NE(coral.rows.size(), find_call(coral.rows, "exec stop_sonar", on));
  ASSERT_TRUE(coral.report.final_depth_m.has_value());
  EXPECT_LT(*coral.report.final_depth_m, 0.3);
}

INSTANTIATE_TEST_SUITE_P(
    EveryScenario, SonarSearch,
    ::testing::Values(Expected{"nominal",
                               Outcome::Completed,
                               {"initialize completed", "dive_from_surface completed", "search completed",
                                "return_to_surface completed"},
                               {"1 completed", "2 completed", "3 completed", "4 completed"},
                               "search: target detected"},
                      Expected{"target_absent",
                               Outcome::Aborted,
                               {"initialize completed", "dive_from_surface completed", "search aborted"},
                               {"1 completed", "2 completed", "3 aborted"},
                               "search: time-out, target not found"},
                      Expected{"leak_search",
                               Outcome::Aborted,
                               {"initialize completed", "dive_from_surface completed", "search aborted"},
                               {"1 completed", "2 completed", "3 aborted"},
                               "search: system problem"}),
    [](const ::testing::TestParamInfo<Expected>& p) { return p.param.scenario; });

// The target (scenario nominal) is behind the vehicle: the looks at 0 to 135
// degrees cannot see it, the look at 180 does.
TEST(SonarSearch, TheTargetIsFoundFromTheHeadingThatFacesIt) {
  SearchRun r = run("sonar_search.coral", "nominal");
  std::vector<std::string> looks;  // "heading: answer" of each target_detected
  std::string heading;
  for (const auto& row : r.rows) {
    if (row.call.starts_with("exec heading ")) heading = row.call.substr(13);
    if (row.call == "ask target_detected") looks.push_back(heading + ": " + row.answer);
  }
  ASSERT_FALSE(looks.empty()) << r.out;
  EXPECT_EQ("180: 1", looks.back());
  for (std::size_t i = 0; i + 1 < looks.size(); ++i) EXPECT_TRUE(looks[i].ends_with(": 0")) << looks[i];
}

// With no target the search goes round every heading before its time runs out.
TEST(SonarSearch, WithoutATargetTheSearchGoesRoundEveryHeading) {
  SearchRun r = run("sonar_search.coral", "target_absent");
  std::vector<std::string> headings;
  for (const auto& row : r.rows) {
    if (row.call.starts_with("exec heading ")) headings.push_back(row.call.substr(13));
    if (row.call == "ask target_detected") {
      EXPECT_EQ("0", row.answer);
    }
  }
  for (const char* h : {"0", "45", "90", "135", "180", "225", "270", "315"}) {
    EXPECT_NE(headings.end(), std::find(headings.begin(), headings.end(), h)) << h;
  }
}

}  // namespace
}  // namespace strata::cli
