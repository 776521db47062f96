// `strata run` of the tank mission, beyond the scenarios: determinism (two
// runs give the same log once the wall_* fields are stripped, also with a
// seed) and a run against a real `strata vehicle` process on a free loopback
// port.
#include <sys/wait.h>

#include "support/tank_run.h"

#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/child_process.h"

namespace strata::cli::run_testing {
namespace {

using namespace std::chrono_literals;

// ---- determinism ------------------------------------------------------------

// Two logs that must be the same run: equal once wall_* fields are stripped,
// so any raw difference is in lines with wall_* fields.
void expect_same_run(const std::string& first, const std::string& second) {
  const std::string a = tactical::strip_wall_fields_from_log(first);
  const std::string b = tactical::strip_wall_fields_from_log(second);
  EXPECT_EQ(std::string::npos, a.find("\"wall_")) << "stripping left a wall_* field";
  ASSERT_FALSE(a.empty());
  if (a == b) return;
  std::istringstream la(a), lb(b);
  std::string x, y;
  for (int n = 1; std::getline(la, x) && std::getline(lb, y); ++n) {
    if (x != y) {
      ADD_FAILURE() << "first difference at line " << n << ":\n  " << x << "\n  " << y;
      return;
    }
  }
  ADD_FAILURE() << "one log is a prefix of the other (" << a.size() << " vs " << b.size() << " bytes)";
}

class Determinism : public ::testing::TestWithParam<std::string> {};

TEST_P(Determinism, TwoRunsLogTheSameOnceWallFieldsAreStripped) {
  const MissionRun& first = scenario_run(GetParam());
  MissionRun second = run_tank(GetParam());
  EXPECT_EQ(first.report.exit_code, second.report.exit_code);
  EXPECT_EQ(first.report.phases, second.report.phases);
  EXPECT_EQ(first.log.lines.size(), second.log.lines.size());
  expect_same_run(first.log.text, second.log.text);
}

INSTANTIATE_TEST_SUITE_P(TankScenarios, Determinism,
                         ::testing::Values("nominal", "weak_thrusters", "leak_phase2", "leak_phase3", "link_loss"));

TEST(DeterminismSeeded, TwoRunsWithTheSameSeedLogTheSame) {
  for (const std::string scenario : {"nominal", "leak_phase3"}) {
    SCOPED_TRACE(scenario);
    MissionRun a = run_tank(scenario, 7);
    MissionRun b = run_tank(scenario, 7);
    ASSERT_FALSE(a.log.lines.size() < 2);
    EXPECT_EQ("choice", a.log.lines[1]["event"]);
    EXPECT_EQ(7, a.log.lines[1]["seed"]);
    EXPECT_EQ(a.report.exit_code, b.report.exit_code);
    EXPECT_EQ(a.report.phases, b.report.phases);
    expect_same_run(a.log.text, b.log.text);
  }
}

// ---- a real `strata vehicle` process ----------------------------------------

TEST(RunAgainstVehicleProcess, NominalMissionCompletes) {
  TempDir dir;
  strata::testing::ChildProcess vehicle(
      {STRATA_BINARY, "vehicle", "--listen", "0", "--scenario", "nominal", "--mission", kMission},
      dir.file("vehicle.err"));
  auto line = vehicle.first_line(10s);
  ASSERT_TRUE(line.has_value()) << "strata vehicle printed no address; stderr:\n" << read_file(dir.file("vehicle.err"));
  ASSERT_EQ(0u, line->rfind("127.0.0.1:", 0)) << *line;
  const std::string address = *line;

  MissionRun r = run_tank("", std::nullopt, address);
  EXPECT_EQ(0, r.report.exit_code) << r.out << r.err;
  EXPECT_EQ((std::vector<std::string>{"initialize completed", "dive_from_surface completed",
                                      "submerge_to_depth completed", "return_to_surface completed"}),
            r.report.phases);
  EXPECT_FALSE(r.report.final_depth_m.has_value()) << "no embedded vehicle to look at";
  EXPECT_FALSE(r.report.emergency_shutdown);
  ASSERT_FALSE(r.log.lines.empty());
  EXPECT_EQ("external", r.log.lines.front()["scenario"]);
  ASSERT_FALSE(r.log.calls.empty());
  EXPECT_EQ("start_network", r.log.calls.front().primitive);
  EXPECT_TRUE(r.log.calls.back().is("shutdown_network", 1));
  EXPECT_NE(std::string::npos, r.out.find("vehicle phoenix-sim at " + address)) << r.out;
  // Its final state is its last telemetry, in the summary and the log.
  ASSERT_TRUE(r.report.last_telemetry.has_value());
  EXPECT_NE(std::string::npos, r.out.find("(its last telemetry)")) << r.out;
  ASSERT_TRUE(r.log.vehicle_final.has_value());
  EXPECT_EQ("telemetry", r.log.at(r.log.vehicle_final)["from"]);
  EXPECT_LT(r.log.at(r.log.vehicle_final)["depth_m"].get<double>(), 0.3);

  // Stopped by its pid (SIGTERM): a clean exit.
  int status = vehicle.stop();
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "status " << status << "; stderr:\n"
                                                             << read_file(dir.file("vehicle.err"));
}

}  // namespace
}  // namespace strata::cli::run_testing
