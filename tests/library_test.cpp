// Strata's phase library (library/, docs/library.md): each phase run in a
// mission against the simulated vehicle in lockstep, in CORAL
// (`import NAME;`) and as rules (`:- use_phase(NAME).`). The two must make
// the same calls with the same answers at the same simulated times (what
// `strata compare` checks), and the calls must be the ones docs/library.md
// lists for the phase, in its order. The missions are tests/library/.
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cli/mission_run.h"
#include "cli/trace_compare.h"
#include "support/tank_run.h"

namespace strata::cli::run_testing::library_phases {
namespace {

const std::string kDir = std::string(STRATA_SOURCE_DIR) + "/tests/library/";

struct PhaseRun {
  RunReport report;
  std::string out, err;
  std::vector<TraceRow> rows;
};

PhaseRun run_phase_mission(const std::string& mission, const std::string& scenario) {
  RunOptions o;
  o.mission = mission;
  o.scenario = scenario;
  o.trace = true;
  std::ostringstream out, err;
  PhaseRun run;
  run.report = run_mission(o, out, err);
  run.out = out.str();
  run.err = err.str();
  run.rows = trace_rows(run.report.trace);
  return run;
}

// The calls as one text, "call -> answer" a line.
std::string calls_text(const std::vector<TraceRow>& rows) {
  std::string text;
  for (const auto& r : rows) text += r.call + " -> " + r.answer + "\n";
  return text;
}

struct Case {
  std::string mission;  // tests/library/NAME.coral and NAME.pl
  std::string scenario;
  Outcome outcome;
  std::vector<std::string> phases;  // the CORAL run's, as the summary gives them
  std::string calls;                // an ECMAScript regex the whole call list must match
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.mission << "/" << c.scenario; }

class LibraryPhase : public ::testing::TestWithParam<Case> {};

TEST_P(LibraryPhase, RunsItsCallsAndTheRulesTwinRunsTheSame) {
  const Case& c = GetParam();
  PhaseRun coral = run_phase_mission(kDir + c.mission + ".coral", c.scenario);
  PhaseRun rules = run_phase_mission(kDir + c.mission + ".pl", c.scenario);
  ASSERT_TRUE(coral.report.result.has_value()) << coral.err;
  ASSERT_TRUE(rules.report.result.has_value()) << rules.err;
  EXPECT_EQ("", coral.err) << "the CORAL mission loads without a warning";
  EXPECT_EQ("", rules.err) << "the rules load without a warning";

  EXPECT_EQ(c.outcome, coral.report.result->outcome) << coral.out;
  EXPECT_EQ(c.outcome, rules.report.result->outcome) << rules.out;
  EXPECT_EQ(c.phases, coral.report.phases) << coral.out;
  EXPECT_EQ(std::nullopt, first_difference(coral.rows, rules.rows))
      << side_by_side(coral.rows, rules.rows, {"CORAL", "PROLOG", std::size_t{5}});
  EXPECT_EQ(coral.report.exit_code, rules.report.exit_code);

  const std::string text = calls_text(coral.rows);
  EXPECT_TRUE(std::regex_match(text, std::regex(c.calls))) << text;
}

// Pieces of the expected call lists.
const std::string kStart = "ood start_network -> 1\n";
const std::string kEnd = "ood shutdown_network -> 1\n";
// n >= 0 times sleep(1) and a "no", then sleep(1) and a "yes".
std::string poll(const std::string& ask) {
  return "(exec sleep 1 -> 1\nask " + ask + " -> 0\n)*exec sleep 1 -> 1\nask " + ask + " -> 1\n";
}
std::string goto_calls(const std::string& x, const std::string& y, const std::string& depth, const std::string& speed) {
  return "exec goto_depth " + depth + " -> 1\nexec set_speed " + speed + " -> 1\nexec goto_xy " + x + " " + y +
         " -> 1\n" + poll("waypoint_reached");
}
const std::string kAbortSurface = "exec stop -> 1\nexec surface -> 1\n" + poll("surface_reached");
// One row: next_row, its end, rows_done.
std::string row(const std::string& done) {
  return "exec next_row -> 1\n" + poll("waypoint_reached") + "ask rows_done -> " + done + "\n";
}
// popup's wait at the surface, and its end: a fix, or none.
const std::string kPopupUp = "exec surface -> 1\n" + poll("surface_reached") + "exec set_timer 20 -> 1\n";
const std::string kPopupFixed = kPopupUp +
                                "(ask gps_available -> 0\nask time_out -> 0\nexec sleep 1 -> 1\n)*"
                                "ask gps_available -> 1\nexec gps_fix -> 1\nexec goto_depth 3 -> 1\n";
const std::string kPopupNoFix = kPopupUp +
                                "(ask gps_available -> 0\nask time_out -> 0\nexec sleep 1 -> 1\n)+"
                                "ask gps_available -> 0\nask time_out -> 1\nexec goto_depth 3 -> 1\n";

INSTANTIATE_TEST_SUITE_P(
    EveryPhase, LibraryPhase,
    ::testing::Values(Case{"goto",
                           "nominal",
                           Outcome::Completed,
                           {"goto completed", "abort_surface completed"},
                           kStart + goto_calls("40", "30", "3", "1") + kAbortSurface + kEnd},
                      Case{"rows",
                           "nominal",
                           Outcome::Completed,
                           {"rows completed", "abort_surface completed"},
                           kStart +
                               "exec goto_depth 3 -> 1\nexec set_speed 1 -> 1\nexec start_rows 0 0 90 40 10 3 -> 1\n" +
                               row("0") + row("0") + row("1") + kAbortSurface + kEnd},
                      Case{"popup",
                           "nominal",
                           Outcome::Completed,
                           {"goto completed", "popup completed", "abort_surface completed"},
                           kStart + goto_calls("30", "0", "3", "1") + kPopupFixed + kAbortSurface + kEnd},
                      Case{"popup",
                           "no_gps",
                           Outcome::Aborted,
                           {"goto completed", "popup aborted", "abort_surface completed"},
                           kStart + goto_calls("30", "0", "3", "1") + kPopupNoFix + kAbortSurface + kEnd},
                      Case{"loiter",
                           "nominal",
                           Outcome::Completed,
                           {"goto completed", "loiter completed", "station_keep completed", "abort_surface completed"},
                           kStart + goto_calls("0", "0", "2", "1") + "exec loiter 20 20 10 -> 1\nexec sleep 60 -> 1\n" +
                               "exec hold_position -> 1\nexec sleep 30 -> 1\n" + kAbortSurface + kEnd}),
    [](const ::testing::TestParamInfo<Case>& p) { return p.param.mission + "_" + p.param.scenario; });

// popup waits at most wait_s at the surface: with no GPS, from set_timer to
// the time_out that ends the wait is the budget, to the poll's second.
TEST(LibraryPopup, GivesUpWhenItsTimeBudgetRunsOut) {
  PhaseRun run = run_phase_mission(kDir + "popup.coral", "no_gps");
  double set_at = -1, out_at = -1;
  for (const auto& r : run.rows) {
    if (r.call == "exec set_timer 20") set_at = r.sim_time_s;
    if (r.call == "ask time_out" && r.answer == "1") out_at = r.sim_time_s;
  }
  ASSERT_GE(set_at, 0) << calls_text(run.rows);
  ASSERT_GE(out_at, 0) << calls_text(run.rows);
  EXPECT_GE(out_at - set_at, 20.0);
  EXPECT_LE(out_at - set_at, 21.5);
}

}  // namespace
}  // namespace strata::cli::run_testing::library_phases
