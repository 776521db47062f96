// The tank mission (missions/tank) driven against the model the way the
// upper levels will call it (tank_mission_driver.h), with the shipped
// parameters and scenarios: each scenario ends the way its file says, and the
// phase windows the fault times were chosen from still hold.
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "vehicle/params.h"
#include "vehicle/scenario.h"
#include "vehicle/tank_mission_driver.h"

namespace strata::vehicle {
namespace {

using testing::MissionRun;
using testing::TankMissionDriver;

const std::string kTimelineDir = std::string(STRATA_SOURCE_DIR) + "/missions/tank/scenarios/";

MissionRun run(const Scenario& scenario) {
  Simulation sim(default_params(), scenario);
  return TankMissionDriver(sim).run();
}

Scenario shipped_scenario(const std::string& name) {
  auto s = load_scenario(kTimelineDir + name);
  EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
  return s.ok() ? s.value() : Scenario{};
}

std::string describe(const MissionRun& m) {
  std::string out;
  for (const auto& p : m.phases) {
    char line[128];
    std::snprintf(line, sizeof line, "phase %d %5.1f-%5.1f s %s\n", p.phase, p.start_s, p.end_s, p.why.c_str());
    out += line;
  }
  return out + (m.completed ? "completed" : "aborted");
}

TEST(TankMission, NominalCompletesForManySeeds) {
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    const MissionRun m = run(Scenario::nominal(seed));
    SCOPED_TRACE(describe(m));
    ASSERT_TRUE(m.completed);
    ASSERT_EQ(4u, m.phases.size());
    EXPECT_NEAR(0.2, m.phases[0].end_s, 1e-9);
    // The windows leak_phase2.toml and leak_phase3.toml rely on.
    EXPECT_LT(m.phases[1].start_s, 4.0);
    EXPECT_GT(m.phases[1].end_s, 4.0 + 3.0);
    EXPECT_LT(m.phases[2].start_s, 14.0 - 2.0);
    EXPECT_GT(m.phases[2].end_s, 14.0 + 3.0);
    // Each phase well inside its timeout (30, 45, 60 s).
    EXPECT_LT(m.phases[1].end_s - m.phases[1].start_s, 20.0);
    EXPECT_LT(m.phases[2].end_s - m.phases[2].start_s, 25.0);
    EXPECT_LT(m.phases[3].end_s - m.phases[3].start_s, 15.0);
  }
}

TEST(TankMission, ShippedNominalCompletes) {
  const MissionRun m = run(shipped_scenario("nominal.toml"));
  std::printf("nominal.toml:\n%s\n", describe(m).c_str());
  EXPECT_TRUE(m.completed) << describe(m);
}

TEST(TankMission, WeakThrustersTimeOutInPhaseTwo) {
  const MissionRun m = run(shipped_scenario("weak_thrusters.toml"));
  ASSERT_EQ(2u, m.phases.size()) << describe(m);
  EXPECT_FALSE(m.completed);
  EXPECT_EQ("time out", m.phases[1].why);
  EXPECT_GT(m.phases[1].end_s, 30.0);
}

TEST(TankMission, LeakInPhaseTwoAbortsPhaseTwo) {
  const Scenario s = shipped_scenario("leak_phase2.toml");
  const MissionRun m = run(s);
  ASSERT_EQ(2u, m.phases.size()) << describe(m);
  EXPECT_EQ("system problem", m.phases[1].why);
  EXPECT_GT(m.phases[1].end_s, s.faults.at(0).at_s);
}

TEST(TankMission, LeakInPhaseThreeAbortsPhaseThree) {
  const Scenario s = shipped_scenario("leak_phase3.toml");
  const MissionRun m = run(s);
  std::printf("leak_phase3.toml:\n%s\n", describe(m).c_str());
  ASSERT_EQ(3u, m.phases.size()) << describe(m);
  EXPECT_TRUE(m.phases[1].completed);
  EXPECT_EQ("system problem", m.phases[2].why);
  EXPECT_LT(m.phases[2].start_s, s.faults.at(0).at_s);
}

}  // namespace
}  // namespace strata::vehicle
