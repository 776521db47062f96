// Runs from the studio: StudioRunner on the tank mission, on the wall clock
// at high speed, told through the EventHub; one at a time; stopped on
// request.
#include "studio/studio_runner.h"

#include <thread>

#include <gtest/gtest.h>

#include "support/tank_run.h"

namespace strata::cli::run_testing {
namespace {

bool wait_for(const std::function<bool()>& done, std::chrono::seconds bound) {
  for (auto end = std::chrono::steady_clock::now() + bound; std::chrono::steady_clock::now() < end;) {
    if (done()) return true;
    std::this_thread::sleep_for(20ms);
  }
  return done();
}

TEST(StudioRun, ATankRunReachesTheEndAndTheSnapshotHasIt) {
  studio::EventHub hub;
  studio::Sandbox sandbox(kTankDir);
  studio::StudioRunner runner(hub, sandbox, tactical::Catalogue::builtin());
  auto sub = hub.subscribe();
  ASSERT_TRUE(runner.start({fs::path(kMission), "tank.coral", "", 200.0}).ok());
  auto again = runner.start({fs::path(kMission), "tank.coral", "", 200.0});
  ASSERT_FALSE(again.ok());
  EXPECT_EQ(core::ErrorCode::Overflow, again.error().code);
  ASSERT_TRUE(wait_for([&] { return !hub.snapshot()["ended"].is_null(); }, 60s));
  const json snap = hub.snapshot();
  EXPECT_EQ("completed", snap["ended"]["outcome"]) << snap["ended"].dump();
  EXPECT_EQ("tank.coral", snap["mission"]);
  EXPECT_EQ(5u, snap["nets"].size());
  EXPECT_GT(snap["telemetry"].size(), 10u);
  // The stream saw the mission net's end: its exit place marked.
  std::string text;
  while (auto chunk = sub->next(10ms)) {
    if (chunk->empty()) break;
    text += *chunk;
  }
  EXPECT_NE(std::string::npos, text.find("\"marking\":{\"closed\":1}")) << text.substr(text.size() > 2000 ? text.size() - 2000 : 0);
}

TEST(StudioRun, StopEndsTheRunAsFailed) {
  studio::EventHub hub;
  studio::Sandbox sandbox(kTankDir);
  studio::StudioRunner runner(hub, sandbox, tactical::Catalogue::builtin());
  ASSERT_TRUE(runner.start({fs::path(kMission), "tank.coral", "", 1.0}).ok());
  ASSERT_TRUE(wait_for([&] { return hub.snapshot()["instances"].size() >= 2; }, 30s));
  runner.stop();
  ASSERT_TRUE(wait_for([&] { return !hub.snapshot()["ended"].is_null(); }, 60s));
  const json ended = hub.snapshot()["ended"];
  EXPECT_EQ("failed", ended["outcome"]);
  EXPECT_NE(std::string::npos, ended["reason"].get<std::string>().find("stopped from the studio")) << ended.dump();
}

TEST(StudioRun, AMissionThatFailsVerificationEndsWithTheReason) {
  studio::EventHub hub;
  studio::Sandbox sandbox(std::string(STRATA_SOURCE_DIR) + "/tests/verify");
  studio::StudioRunner runner(hub, sandbox, tactical::Catalogue::builtin());
  ASSERT_TRUE(runner.start({fs::path(STRATA_SOURCE_DIR) / "tests/verify/dead_branch.coral", "dead_branch.coral", "", 10.0}).ok());
  ASSERT_TRUE(wait_for([&] { return !hub.snapshot()["ended"].is_null(); }, 30s));
  EXPECT_NE(std::string::npos, hub.snapshot()["ended"]["reason"].get<std::string>().find("fails verification"));
}

}  // namespace
}  // namespace strata::cli::run_testing
