// `strata run` verifies a CORAL mission before anything moves: a mission
// that fails is refused, unless --unverified, and then the log says so.
#include "support/tank_run.h"

#include <sstream>
#include <string>

#include <gtest/gtest.h>

namespace strata::cli::run_testing {
namespace {

const std::string kDeadBranch = std::string(STRATA_SOURCE_DIR) + "/tests/verify/dead_branch.coral";

std::optional<json> verification_line(const ParsedLog& log) {
  for (const auto& line : log.lines) {
    if (line.value("event", "") == "verification") return line;
  }
  return std::nullopt;
}

TEST(RunVerify, AMissionThatFailsVerificationIsNotRun) {
  RunOptions o;
  o.mission = kDeadBranch;
  std::ostringstream out, err;
  RunReport r = run_mission(o, out, err);
  EXPECT_EQ(65, r.exit_code);
  EXPECT_FALSE(r.result.has_value());
  EXPECT_EQ(0u, r.primitive_calls);
  EXPECT_NE(std::string::npos, err.str().find("FAIL  no_dead          never fires: never_used (spare is never marked)"))
      << err.str();
  EXPECT_NE(std::string::npos, err.str().find("fails verification; not running")) << err.str();
  EXPECT_EQ("", out.str());  // the vehicle was never started
}

TEST(RunVerify, UnverifiedRunsItAndTheLogRecordsTheFailures) {
  TempDir dir;
  RunOptions o;
  o.mission = kDeadBranch;
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
  EXPECT_EQ("dead_branch", v->at("failed")[0].at("net"));
  EXPECT_EQ("no_dead", v->at("failed")[0].at("property"));
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
