// `strata run` verifies a CORAL mission before anything moves: a mission
// that fails a property that blocks a run is refused, unless --unverified,
// and then the log says so; one that only has warnings (one_safe, no_dead)
// runs, and the log lists them.
#include "support/tank_run.h"

#include <sstream>
#include <string>

#include <gtest/gtest.h>

namespace strata::cli::run_testing {
namespace {

const std::string kExitsTogether = std::string(STRATA_SOURCE_DIR) + "/tests/verify/exits_together.coral";
const std::string kDeadBranch = std::string(STRATA_SOURCE_DIR) + "/tests/verify/dead_branch.coral";
const std::string kCounting = std::string(STRATA_SOURCE_DIR) + "/tests/run/counting.coral";

std::optional<json> verification_line(const ParsedLog& log) {
  for (const auto& line : log.lines) {
    if (line.value("event", "") == "verification") return line;
  }
  return std::nullopt;
}

TEST(RunVerify, AMissionThatFailsVerificationIsNotRun) {
  RunOptions o;
  o.mission = kExitsTogether;
  std::ostringstream out, err;
  RunReport r = run_mission(o, out, err);
  EXPECT_EQ(65, r.exit_code);
  EXPECT_FALSE(r.result.has_value());
  EXPECT_EQ(0u, r.primitive_calls);
  EXPECT_NE(std::string::npos, err.str().find("FAIL  exits_exclusive  exits closed, also_closed are marked together"))
      << err.str();
  EXPECT_NE(std::string::npos, err.str().find("fails verification; not running")) << err.str();
  EXPECT_EQ("", out.str());  // the vehicle was never started
}

TEST(RunVerify, UnverifiedRunsItAndTheLogRecordsTheFailures) {
  TempDir dir;
  RunOptions o;
  o.mission = kExitsTogether;
  o.unverified = true;
  o.log = dir.file("mission.jsonl");
  std::ostringstream out, err;
  RunReport r = run_mission(o, out, err);
  EXPECT_EQ(0, r.exit_code) << err.str();
  ASSERT_TRUE(r.result.has_value());
  EXPECT_EQ(Outcome::Completed, r.result->outcome);
  EXPECT_NE(std::string::npos, err.str().find("running a mission that fails verification (--unverified)"));
  ParsedLog log = parse_log(read_file(o.log));
  auto v = verification_line(log);
  ASSERT_TRUE(v.has_value());
  EXPECT_FALSE(v->at("ok").get<bool>());
  EXPECT_TRUE(v->at("run_anyway").get<bool>());
  ASSERT_EQ(1u, v->at("failed").size());
  EXPECT_EQ("exits_together", v->at("failed")[0].at("net"));
  EXPECT_EQ("exits_exclusive", v->at("failed")[0].at("property"));
}

// Regression: a dead transition made `strata run` refuse the mission (exit
// 65); it is a warning, printed, and recorded in the log.
TEST(RunVerify, ADeadTransitionIsAWarningAndTheMissionRuns) {
  TempDir dir;
  RunOptions o;
  o.mission = kDeadBranch;
  o.log = dir.file("mission.jsonl");
  std::ostringstream out, err;
  RunReport r = run_mission(o, out, err);
  EXPECT_EQ(0, r.exit_code) << err.str();
  ASSERT_TRUE(r.result.has_value());
  EXPECT_EQ(Outcome::Completed, r.result->outcome);
  EXPECT_NE(std::string::npos, err.str().find("warn  no_dead          never fires: never_used (spare is never marked)"))
      << err.str();
  auto v = verification_line(parse_log(read_file(o.log)));
  ASSERT_TRUE(v.has_value());
  EXPECT_TRUE(v->at("ok").get<bool>());
  EXPECT_FALSE(v->contains("failed"));
  ASSERT_EQ(1u, v->at("warnings").size());
  EXPECT_EQ("no_dead", v->at("warnings")[0].at("property"));
}

// Regression: any place that may hold two tokens failed one_safe and the
// mission was refused; the engine runs any bounded net (weights, counters).
TEST(RunVerify, PlacesWithSeveralTokensAndArcWeightsRun) {
  RunOptions o;
  o.mission = kCounting;
  std::ostringstream out, err;
  RunReport r = run_mission(o, out, err);
  EXPECT_EQ(0, r.exit_code) << err.str();
  ASSERT_TRUE(r.result.has_value());
  EXPECT_EQ(Outcome::Completed, r.result->outcome);
  EXPECT_EQ(6u, r.primitive_calls);  // four sleeps, the report, the shutdown
  EXPECT_NE(std::string::npos, err.str().find("warn  one_safe         bolts can hold 4 tokens")) << err.str();
}

TEST(RunVerify, TheTankMissionIsVerifiedAndTheLogSaysSo) {
  const MissionRun& run = scenario_run("nominal");
  auto v = verification_line(run.log);
  ASSERT_TRUE(v.has_value());
  EXPECT_TRUE(v->at("ok").get<bool>());
  EXPECT_EQ(5u, v->at("nets").get<std::size_t>());
  EXPECT_FALSE(v->contains("failed"));
}

}  // namespace
}  // namespace strata::cli::run_testing
