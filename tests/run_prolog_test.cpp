// `strata run` of the PROLOG tank mission (missions/tank/tank.pl) in every
// shipped scenario, checked against the CORAL mission call by call (what
// `strata compare` does); the paper's own Figure 10 in place of our phase 2;
// rules that loop, recurse or fail, which must end with the vehicle
// surfaced; and guards (docs/prolog.md §8) polled beside a blocking call
// in lockstep. Helpers: support/tank_run.h.
#include "support/tank_run.h"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cli/trace_compare.h"

namespace strata::cli::run_testing {
namespace {

const std::string kRules = kTankDir + "/tank.pl";
const std::string kFixtures = std::string(STRATA_SOURCE_DIR) + "/tests/run";
// The paper's text (not part of the project: a user's clone has no ../shared).
const std::string kPaper = std::string(STRATA_SOURCE_DIR) + "/../shared/seed/000_00d9d75137f20be2.txt";

struct TracedRun {
  RunReport report;
  std::string out, err;
  std::vector<TraceRow> rows;
};

TracedRun run_traced(const std::string& mission, const std::string& scenario,
                     std::uint64_t inference_limit = RunOptions{}.inference_limit) {
  RunOptions o;
  o.mission = mission;
  o.scenario = scenario;
  o.trace = true;
  o.inference_limit = inference_limit;
  std::ostringstream out, err;
  TracedRun run;
  run.report = run_mission(o, out, err);
  run.out = out.str();
  run.err = err.str();
  run.rows = trace_rows(run.report.trace);
  return run;
}

std::string table(const TracedRun& a, const TracedRun& b) {
  return side_by_side(a.rows, b.rows, {"CORAL", "PROLOG", std::size_t{5}});
}

struct Expected {
  std::string scenario;
  Outcome outcome;
  std::vector<std::string> phases;
};

void PrintTo(const Expected& e, std::ostream* os) { *os << e.scenario; }

class TankRules : public ::testing::TestWithParam<Expected> {};

TEST_P(TankRules, BehaveAsTheNetCallForCall) {
  const Expected& e = GetParam();
  TracedRun coral = run_traced(kMission, e.scenario);
  TracedRun rules = run_traced(kRules, e.scenario);
  ASSERT_TRUE(rules.report.result.has_value()) << rules.err;
  EXPECT_EQ("", rules.err) << "our rules load without a warning";

  EXPECT_FALSE(rules.rows.empty());
  EXPECT_EQ(std::nullopt, first_difference(coral.rows, rules.rows)) << table(coral, rules);
  EXPECT_EQ(coral.report.primitive_calls, rules.report.primitive_calls);
  EXPECT_EQ(e.outcome, rules.report.result->outcome) << rules.out;
  EXPECT_EQ(coral.report.result->outcome, rules.report.result->outcome);
  EXPECT_EQ(coral.report.exit_code, rules.report.exit_code);
  EXPECT_EQ(e.phases, rules.report.phases) << rules.out;
  EXPECT_NEAR(coral.report.sim_time_s, rules.report.sim_time_s, 1e-9);
  ASSERT_TRUE(rules.report.final_depth_m.has_value());
  EXPECT_NEAR(*coral.report.final_depth_m, *rules.report.final_depth_m, 1e-9);
  EXPECT_EQ(coral.report.emergency_shutdown, rules.report.emergency_shutdown);
  EXPECT_EQ(coral.report.vehicle_watchdog_tripped, rules.report.vehicle_watchdog_tripped);
}

INSTANTIATE_TEST_SUITE_P(
    EveryScenario, TankRules,
    ::testing::Values(
        Expected{"nominal", Outcome::Completed, {"1 completed", "2 completed", "3 completed", "4 completed"}},
        Expected{"weak_thrusters", Outcome::Aborted, {"1 completed", "2 aborted"}},
        Expected{"leak_phase2", Outcome::Aborted, {"1 completed", "2 aborted"}},
        Expected{"leak_phase3", Outcome::Aborted, {"1 completed", "2 completed", "3 aborted"}},
        Expected{"link_loss", Outcome::Failed, {"1 completed", "2 cancelled"}}),
    [](const ::testing::TestParamInfo<Expected>& p) { return p.param.scenario; });

TEST(TankRules, TheLogRecordsTheRulesPhasesAndEnd) {
  TempDir dir;
  RunOptions o;
  o.mission = kRules;
  o.log = dir.file("rules.jsonl");
  std::ostringstream out, err;
  RunReport r = run_mission(o, out, err);
  ASSERT_EQ(0, r.exit_code) << out.str() << err.str();
  ParsedLog log = parse_log(read_file(o.log));
  EXPECT_EQ((std::vector<std::string>{"1", "2", "3", "4"}), log.started);
  ASSERT_TRUE(log.mission_end.has_value());
  EXPECT_EQ("completed", log.at(log.mission_end)["outcome"]);
  EXPECT_EQ(80u, log.calls.size());
  EXPECT_NE(std::string::npos, out.str().find("mission tank: completed")) << out.str();
}

// Figure 10 of the paper, verbatim, as phase2.pl of a copy of the tank folder.
std::string figure10() {
  std::ifstream in(kPaper);
  std::string line, text;
  bool after_caption = false, inside = false;
  while (std::getline(in, line)) {
    if (!after_caption) {
      after_caption = line.starts_with("Figure 9:");
      continue;
    }
    if (line.starts_with("```")) {
      if (inside) return text;
      inside = true;
      continue;
    }
    if (inside) text += line + "\n";
  }
  return "";
}

TEST(Figure10, RunsUnchangedAndBehavesAsOurPhase2InEveryScenario) {
  if (!fs::exists(kPaper))
    GTEST_SKIP() << "skipped: ../shared/seed not present (the paper's text is not in the project)";
  const std::string fig10 = figure10();
  ASSERT_NE(std::string::npos, fig10.find("execute_phase(2)")) << "Figure 10 not found after the Figure 9 caption";
  ASSERT_NE(std::string::npos, fig10.find("done:- current_phase(mission_abort)"));

  TempDir dir;
  const fs::path copy = dir.file("tank");
  fs::copy(kTankDir, copy, fs::copy_options::recursive);
  std::ofstream(copy / "phase2.pl", std::ios::trunc) << fig10;
  const std::string paper_rules = (copy / "tank.pl").string();

  for (const std::string scenario : {"nominal", "weak_thrusters", "leak_phase2", "leak_phase3", "link_loss"}) {
    SCOPED_TRACE(scenario);
    TracedRun ours = run_traced(kRules, scenario);
    TracedRun paper = run_traced(paper_rules, scenario);
    ASSERT_TRUE(paper.report.result.has_value()) << paper.err;
    EXPECT_NE(std::string::npos, paper.err.find("phase2.pl"))
        << "Figure 10's singleton X is warned about, with its file";
    EXPECT_EQ(std::string::npos, paper.err.find("error")) << paper.err;
    EXPECT_EQ(std::nullopt, first_difference(ours.rows, paper.rows))
        << side_by_side(ours.rows, paper.rows, {"ours", "Figure 10", std::size_t{5}});
    EXPECT_EQ(ours.report.result->outcome, paper.report.result->outcome);
    EXPECT_EQ(ours.report.phases, paper.report.phases);
    EXPECT_EQ(ours.report.exit_code, paper.report.exit_code);
  }
}

// Rules that never call a primitive again: stopped by the inference limit,
// then the runner surfaces the vehicle and shuts the network down.
TEST(BadRules, AnEndlessLoopIsStoppedAndTheVehicleSurfaced) {
  TracedRun r = run_traced(kFixtures + "/loop_at_depth.pl", "", 1'000'000);
  ASSERT_TRUE(r.report.result.has_value()) << r.err;
  EXPECT_EQ(Outcome::Failed, r.report.result->outcome);
  EXPECT_EQ(1, r.report.exit_code);
  EXPECT_NE(std::string::npos, r.report.result->reason.find("1000000 inferences without calling a primitive"))
      << r.report.result->reason;
  EXPECT_NE(std::string::npos, r.out.find("failed: the Strategic level could not go on")) << r.out;
  EXPECT_TRUE(r.report.emergency_surface);
  EXPECT_TRUE(r.report.emergency_surfaced) << r.out;
  EXPECT_TRUE(r.report.emergency_shutdown);
  ASSERT_TRUE(r.report.final_depth_m.has_value());
  EXPECT_LE(*r.report.final_depth_m, kParams.surface_depth_m) << r.out;
  // It was under water when the rules stopped: the surfacing is the runner's.
  const std::string trace = side_by_side(r.rows, {}, {});
  auto surface =
      std::find_if(r.rows.begin(), r.rows.end(), [](const TraceRow& row) { return row.call == "exec surface"; });
  ASSERT_NE(r.rows.end(), surface) << trace;
  ASSERT_NE(r.rows.begin(), surface);
  EXPECT_EQ("ask surface_reached", (surface - 1)->call) << "asked first: " << trace;
  EXPECT_EQ("0", (surface - 1)->answer) << "under water when the rules stopped: " << trace;
  ASSERT_GE(r.rows.size(), 3u);
  EXPECT_EQ("ask surface_reached", r.rows[r.rows.size() - 2].call);
  EXPECT_EQ("1", r.rows[r.rows.size() - 2].answer);
  EXPECT_EQ("ood shutdown_network", r.rows.back().call);
}

TEST(BadRules, EndlessRecursionIsStoppedAndTheVehicleSurfaced) {
  TracedRun r = run_traced(kFixtures + "/recurse_at_depth.pl", "");
  ASSERT_TRUE(r.report.result.has_value()) << r.err;
  EXPECT_EQ(Outcome::Failed, r.report.result->outcome);
  const std::string& why = r.report.result->reason;
  EXPECT_TRUE(why.find("out of Prolog stack") != std::string::npos || why.find("inferences") != std::string::npos)
      << why;
  EXPECT_TRUE(r.report.emergency_surfaced) << r.out;
  ASSERT_TRUE(r.report.final_depth_m.has_value());
  EXPECT_LE(*r.report.final_depth_m, kParams.surface_depth_m);
}

// Regression (issue 39): a phase2.pl with no clauses made the tank mission
// restart phase 2 until the inference limit: 1.67 M lines and 67 MB on
// stdout, a 9.2 MB summary line, 127 MB of log. Now the log's bound ends the
// run safely with its reason, the console says a repeated line three times
// then counts it, and the summary's phases are one entry with a count.
TEST(BadRules, APhaseRestartedInALoopIsBoundedInLogConsoleAndSummary) {
  TempDir dir;
  const fs::path copy = dir.file("tank");
  fs::copy(kTankDir, copy, fs::copy_options::recursive);
  std::ofstream(copy / "phase2.pl", std::ios::trunc) << "% no clauses\n";
  RunOptions o;
  o.mission = (copy / "tank.pl").string();
  o.log = (copy / "run.jsonl").string();
  o.max_log_bytes = 1u << 20;
  std::ostringstream out, err;
  const RunReport report = run_mission(o, out, err);
  ASSERT_TRUE(report.result.has_value()) << err.str();
  EXPECT_EQ(Outcome::Failed, report.result->outcome);
  EXPECT_EQ("limit", report.stopped_by);
  EXPECT_EQ(1, report.exit_code);
  EXPECT_NE(std::string::npos, report.result->reason.find("the mission log reached its limit of 1 MB"))
      << report.result->reason;
  EXPECT_LE(fs::file_size(copy / "run.jsonl"), o.max_log_bytes);
  const std::string log = read_file((copy / "run.jsonl").string());
  EXPECT_NE(std::string::npos, log.find("\"event\":\"log_limit\"")) << "the log says where it was cut";
  EXPECT_NE(std::string::npos, log.find("\"event\":\"mission_end\"")) << "the end fits in the reserve";
  ASSERT_TRUE(report.final_depth_m.has_value());
  EXPECT_LE(*report.final_depth_m, kParams.surface_depth_m);
  // The console: three of each repeated line, then a count.
  const std::string text = out.str();
  EXPECT_LT(text.size(), 4000u) << text.substr(0, 4000);
  EXPECT_NE(std::string::npos, text.find("repeated lines not shown")) << text;
  // The summary: 2 aborted, once, with its count.
  ASSERT_GE(report.phases.size(), 2u);
  EXPECT_LE(report.phases.size(), 4u);
  EXPECT_EQ("1 completed", report.phases[0]);
  EXPECT_EQ(0u, report.phases[1].find("2 aborted (x")) << report.phases[1];
}

TEST(BadRules, AnExceptionInTheRulesEndsTheMissionWithItsText) {
  TracedRun r = run_traced(kFixtures + "/raises_at_depth.pl", "");
  ASSERT_TRUE(r.report.result.has_value()) << r.err;
  EXPECT_EQ(Outcome::Failed, r.report.result->outcome);
  EXPECT_NE(std::string::npos, r.report.result->reason.find("evaluation_error(zero_divisor)"))
      << r.report.result->reason;
  EXPECT_TRUE(r.report.emergency_surfaced);
}

// tests/run/guarded_dive.pl: a mission-wide guard on system_problem (2 s)
// and a phase guard on not(depth_reached) (5 s) beside a five-minute sleep.
const std::string kGuarded = kFixtures + "/guarded_dive.pl";

std::vector<const json*> lines_of(const ParsedLog& log, std::string_view event) {
  std::vector<const json*> out;
  for (const auto& j : log.lines) {
    if (j["event"] == event) out.push_back(&j);
  }
  return out;
}

TEST(GuardedRules, PollsRunBesideABlockingCallAndTripOnNothing) {
  RunOptions o;
  o.mission = kGuarded;
  MissionRun r = run_logged(o);
  ASSERT_EQ(0, r.report.exit_code) << r.out << r.err;
  EXPECT_EQ("", r.err);
  EXPECT_TRUE(lines_of(r.log, "guard_tripped").empty());
  // While the rules wait 300 s in one sleep, the guards poll on: system_problem
  // every 2.1 s (a 2 s sleep, a 0.1 s ask), depth_reached every 5.1 s.
  const Call* hold = r.log.first([](const Call& c) { return c.primitive == "sleep" && c.phase == "hold"; });
  ASSERT_NE(nullptr, hold);
  auto during_hold = [&](std::string_view primitive) {
    return r.log.count([&](const Call& c) {
      return c.primitive == primitive && c.requested_s > hold->requested_s && c.requested_s < hold->replied_s;
    });
  };
  EXPECT_EQ(142u, during_hold("system_problem"));  // 300 / 2.1
  EXPECT_EQ(58u, during_hold("depth_reached"));    // 300 / 5.1, the phase's guard: only in the phase
  EXPECT_EQ(0u, r.log.count([&](const Call& c) {
    return c.primitive == "depth_reached" && c.requested_s > hold->replied_s + kEps;
  })) << "the phase guard stops with its phase";
}

TEST(GuardedRules, ALeakPreemptsTheSleepWithinOnePollAndTheHandlerSurfaces) {
  RunOptions o;
  o.mission = kGuarded;
  o.scenario = kFixtures + "/guarded_leak.toml";
  MissionRun r = run_logged(o);
  ASSERT_TRUE(r.report.result.has_value()) << r.err;
  EXPECT_EQ(Outcome::Aborted, r.report.result->outcome) << r.out;
  EXPECT_EQ(1, r.report.exit_code);
  auto trips = lines_of(r.log, "guard_tripped");
  ASSERT_EQ(1u, trips.size()) << r.out;
  const json& trip = *trips[0];
  EXPECT_EQ("leak", trip["guard"]);
  EXPECT_EQ("system_problem", trip["condition"]);
  EXPECT_EQ(0, trip["instance"]);
  EXPECT_EQ(json::array({"hold (instance 1)"}), trip["preempted_phases"]);
  // The hold's sleep and the phase guard's sleep.
  EXPECT_EQ(json::array({"exec sleep", "exec sleep"}), trip["preempted_calls"]);
  // The leak starts at 90 s: found at the guard's next ask, at most one
  // period and one ask later.
  const double tripped_s = trip["sim_time"];
  EXPECT_GE(tripped_s, 90.0);
  EXPECT_LE(tripped_s, 90.0 + 2.0 + 0.1 + kEps);
  // The handler's first call (after its REPORT) goes out at the trip.
  const Call* surface = r.log.first([&](const Call& c) { return c.primitive == "surface"; });
  ASSERT_NE(nullptr, surface);
  EXPECT_NEAR(tripped_s, surface->requested_s, kEps);
  EXPECT_LT(r.report.sim_time_s, 150.0) << "the pre-empted 300 s sleep held nothing";
  EXPECT_FALSE(r.report.emergency_surfaced) << "the handler surfaced and shut down itself";
  ASSERT_TRUE(r.report.final_depth_m.has_value());
  EXPECT_LE(*r.report.final_depth_m, kParams.surface_depth_m);
  EXPECT_EQ((std::vector<std::string>{"hold cancelled"}), r.report.phases);
}

// The guarded survey (missions/survey: a leak guard for the whole mission, a
// hazard guard per leg) as rules, against the net: the same calls at the same
// times in every shipped scenario and with each kind of fault at a moment
// where a guard or the mission's own checks must act (a sensor dropout is a
// system problem: the leak guard's).
const std::string kSurveyDir = std::string(STRATA_SOURCE_DIR) + "/missions/survey";

struct SurveyCase {
  std::string name;
  std::string scenario;  // a shipped scenario's name, or "" for the fault below in nominal's water
  std::string fault;     // TOML lines of one [[fault]]
  Outcome outcome;
  std::string report;  // a REPORT the runs must make ("" for none required)
};

void PrintTo(const SurveyCase& c, std::ostream* os) { *os << c.name; }

class SurveyRules : public ::testing::TestWithParam<SurveyCase> {};

TEST_P(SurveyRules, BehaveAsTheGuardedNetCallForCall) {
  const SurveyCase& c = GetParam();
  TempDir dir;
  std::string scenario = c.scenario;
  if (scenario.empty()) {
    scenario = dir.file(c.name + ".toml");
    std::ofstream(scenario) << read_file(kSurveyDir + "/scenarios/nominal.toml") << "[[fault]]\n" << c.fault;
  }
  TracedRun coral = run_traced(kSurveyDir + "/survey.coral", scenario);
  TracedRun rules = run_traced(kSurveyDir + "/survey.pl", scenario);
  ASSERT_TRUE(coral.report.result.has_value()) << coral.err;
  ASSERT_TRUE(rules.report.result.has_value()) << rules.err;
  EXPECT_EQ("", rules.err) << "the rules load without a warning";
  EXPECT_EQ(std::nullopt, first_difference(coral.rows, rules.rows)) << table(coral, rules);
  EXPECT_EQ(c.outcome, coral.report.result->outcome) << coral.out;
  EXPECT_EQ(c.outcome, rules.report.result->outcome) << rules.out;
  // A failure in the same words (an abort's reason is each executor's own).
  if (c.outcome == Outcome::Failed) {
    EXPECT_EQ(coral.report.result->reason, rules.report.result->reason);
  }
  EXPECT_EQ(coral.report.exit_code, rules.report.exit_code);
  EXPECT_NEAR(coral.report.sim_time_s, rules.report.sim_time_s, 1e-9);
  if (!c.report.empty()) {
    EXPECT_TRUE(std::any_of(rules.rows.begin(), rules.rows.end(),
                            [&](const TraceRow& r) { return r.call.find(c.report) != std::string::npos; }))
        << c.report << " not reported:\n"
        << rules.out;
  }
}

const char* const kLeak = "survey aborted: a problem on board";
const char* const kHazard = "leg: the seabed is under the floor, or the position is uncertain";

INSTANTIATE_TEST_SUITE_P(
    ScenariosAndFaults, SurveyRules,
    ::testing::Values(SurveyCase{"nominal", "nominal", "", Outcome::Completed, ""},
                      SurveyCase{"leak", "leak", "", Outcome::Aborted, kLeak},
                      SurveyCase{"shallow", "shallow", "", Outcome::Aborted, kHazard},
                      SurveyCase{"lost_position", "lost_position", "", Outcome::Aborted, ""},
                      // In the two minutes at the surface, in leg 2, in a refix, in the recovery.
                      SurveyCase{"leak_at_the_surface", "", "kind = \"leak\"\nat_s = 60.0\n", Outcome::Aborted, kLeak},
                      SurveyCase{"leak_in_leg_2", "", "kind = \"leak\"\nat_s = 600.0\n", Outcome::Aborted, kLeak},
                      SurveyCase{"leak_in_a_refix", "", "kind = \"leak\"\nat_s = 460.0\n", Outcome::Aborted, kLeak},
                      SurveyCase{"leak_at_the_end", "", "kind = \"leak\"\nat_s = 1570.0\n", Outcome::Aborted, kLeak},
                      SurveyCase{"altimeter_dead_in_leg_1", "", "kind = \"altimeter_dead\"\nat_s = 200.0\n",
                                 Outcome::Aborted, kHazard},
                      SurveyCase{"weak_thrusters", "", "kind = \"weak_thrusters\"\nat_s = 420.0\nhealth = 0.4\n",
                                 Outcome::Completed, ""},
                      SurveyCase{"sensor_dropout", "", "kind = \"sensor_dropout\"\nat_s = 330.0\nduration_s = 20.0\n",
                                 Outcome::Aborted, kLeak},
                      SurveyCase{"compass_bias", "", "kind = \"compass_bias\"\nat_s = 5.0\nbias_deg = 20.0\n",
                                 Outcome::Completed, ""},
                      SurveyCase{"no_gps", "", "kind = \"no_gps\"\nat_s = 130.0\n", Outcome::Failed, ""},
                      SurveyCase{"link_loss", "", "kind = \"link_loss\"\nat_s = 330.0\nduration_s = 5.0\n",
                                 Outcome::Failed, ""}),
    [](const ::testing::TestParamInfo<SurveyCase>& p) { return p.param.name; });

}  // namespace
}  // namespace strata::cli::run_testing
