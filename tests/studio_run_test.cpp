// Runs from the studio: StudioRunner on a copy of the tank mission, on the
// wall clock at high speed, told through the EventHub; one at a time;
// aborted (the safe end) or stopped hard on request; each run's log in
// runs/ beside the mission; inputs read through the studio's sandbox.
#include "studio/studio_runner.h"

#include <algorithm>
#include <set>
#include <thread>

#include <gtest/gtest.h>

#include "studio/replay.h"
#include "support/tank_run.h"
#include "vehicle/params.h"

namespace strata::cli::run_testing {
namespace {

// "At the surface" as the vehicle says it (surface_reached: its depth
// estimate at or above surface_depth_m), in true depth: the estimate may be
// a few of the depth cell's standard deviations off. How far above that the
// vehicle has risen by the run's end depends on the wall clock (these runs
// are real time), so no tighter figure holds on a loaded machine.
double surfaced_depth_m() {
  const auto p = vehicle::default_params();
  return p.surface_depth_m + 5 * p.depth_noise_m;
}

bool wait_for(const std::function<bool()>& done, std::chrono::seconds bound) {
  for (auto end = std::chrono::steady_clock::now() + bound; std::chrono::steady_clock::now() < end;) {
    if (done()) return true;
    std::this_thread::sleep_for(20ms);
  }
  return done();
}

// A studio on a fresh copy of missions/tank (runs write runs/ beside it).
class StudioRunTest : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::create_directories(root() / "studio");
    fs::copy(kTankDir, studio() / "tank", fs::copy_options::recursive);
    fs::remove_all(studio() / "tank/runs");
    sandbox_.emplace(studio());
    runner_.emplace(hub_, *sandbox_, tactical::Catalogue::builtin());
  }
  void TearDown() override { runner_.reset(); }
  // The test's folder: the studio's folder, and `outside` beside it.
  fs::path root() const { return fs::path(dir_.file("x")).parent_path(); }
  fs::path studio() const { return root() / "studio"; }
  studio::RunRequest request(double speed, const std::string& mission = "tank/tank.coral") {
    return {fs::canonical(studio() / mission), mission, "", speed};
  }
  bool ended(std::chrono::seconds bound = 60s) {
    return wait_for([&] { return !hub_.snapshot()["ended"].is_null(); }, bound);
  }
  // The depth of the last telemetry sample.
  double depth() {
    const json t = hub_.snapshot()["telemetry"];
    return t.empty() ? 0.0 : t.back()[1].get<double>();
  }
  std::vector<fs::path> logs() {
    std::vector<fs::path> out;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(studio() / "tank/runs", ec)) out.push_back(e.path());
    return out;
  }
  std::vector<json> lines(const fs::path& log) {
    std::vector<json> out;
    std::ifstream in(log);
    for (std::string line; std::getline(in, line);) out.push_back(json::parse(line));
    return out;
  }

  TempDir dir_;
  studio::EventHub hub_;
  std::optional<studio::Sandbox> sandbox_;
  std::optional<studio::StudioRunner> runner_;
};

TEST_F(StudioRunTest, ATankRunReachesTheEndAndTheSnapshotHasIt) {
  auto sub = hub_.subscribe();
  ASSERT_TRUE(runner_->start(request(200.0)).ok());
  auto again = runner_->start(request(200.0));
  ASSERT_FALSE(again.ok());
  EXPECT_EQ(core::ErrorCode::Overflow, again.error().code);
  ASSERT_TRUE(ended());
  const json snap = hub_.snapshot();
  EXPECT_EQ("completed", snap["ended"]["outcome"]) << snap["ended"].dump();
  EXPECT_EQ("tank/tank.coral", snap["mission"]);
  EXPECT_EQ(5u, snap["nets"].size());
  EXPECT_GT(snap["telemetry"].size(), 10u);
  // The stream saw the mission net's end: its exit place marked.
  std::string text;
  while (auto chunk = sub->next(10ms)) {
    if (chunk->empty()) break;
    text += *chunk;
  }
  EXPECT_NE(std::string::npos, text.find("\"marking\":{\"closed\":1}"))
      << text.substr(text.size() > 2000 ? text.size() - 2000 : 0);
}

// Issue 17: finished phases stayed "in flight" to the end of the run, in the
// page and in the server's snapshot: the engine ends a PHASE action with the
// phase, not with an answer to its id.
TEST_F(StudioRunTest, FinishedPhasesStayedInFlightToTheEndOfTheRun) {
  auto sub = hub_.subscribe();
  ASSERT_TRUE(runner_->start(request(200.0)).ok());
  // While it runs: every PHASE action in flight belongs to a phase running.
  bool looked_mid_run = false;
  for (auto bound = std::chrono::steady_clock::now() + 60s; std::chrono::steady_clock::now() < bound;) {
    const json snap = hub_.snapshot();
    if (!snap["ended"].is_null()) break;
    std::set<std::string> running;
    for (const auto& i : snap["instances"]) running.insert(i["net"].get<std::string>());
    // The engine starts a PHASE action, then its phase: between the two,
    // the newest action in flight may be a phase not running yet. Any
    // other PHASE action in flight must be a phase that runs.
    std::uint64_t newest = 0;
    for (const auto& f : snap["in_flight"]) newest = std::max(newest, f["id"].get<std::uint64_t>());
    for (const auto& f : snap["in_flight"]) {
      if (f["kind"] != "phase") continue;
      const bool runs = running.count(f["primitive"].get<std::string>()) > 0;
      EXPECT_TRUE(runs || f["id"].get<std::uint64_t>() == newest) << snap.dump();
      looked_mid_run = looked_mid_run || runs;
    }
    std::this_thread::sleep_for(5ms);
  }
  ASSERT_TRUE(ended());
  EXPECT_TRUE(looked_mid_run);
  std::string text;
  while (auto chunk = sub->next(10ms)) {
    if (chunk->empty()) break;
    text += *chunk;
  }
  // In the stream: each PHASE action ends, with an action_finish of its id
  // or with its phase_end's "action".
  std::set<std::uint64_t> phases_started, phases_ended;
  std::istringstream in(text);
  std::string event;
  for (std::string line; std::getline(in, line);) {
    if (line.starts_with("event: ")) event = line.substr(7);
    if (!line.starts_with("data: ")) continue;
    const json d = json::parse(line.substr(6));
    if (event == "action_start" && d["kind"] == "phase") phases_started.insert(d["id"].get<std::uint64_t>());
    if (event == "action_finish") phases_ended.insert(d["id"].get<std::uint64_t>());
    if (event == "phase_end") phases_ended.insert(d["action"].get<std::uint64_t>());
  }
  EXPECT_EQ(4u, phases_started.size());
  for (auto id : phases_started) EXPECT_TRUE(phases_ended.count(id)) << "PHASE action " << id << " never ended";
  // Final markings stay after the run: the mission net holds `closed`.
  const json snap = hub_.snapshot();
  EXPECT_TRUE(snap["in_flight"].empty());
  bool mission_final = false;
  for (const auto& f : snap["final"]) {
    if (f["net"] == "tank") {
      mission_final = true;
      EXPECT_EQ(json({{"closed", 1}}), f["marking"]) << f.dump();
    }
  }
  EXPECT_TRUE(mission_final) << snap["final"].dump();
}

// Issue 17: Stop left the vehicle at 1.25 m, shown as a red "failed". Abort
// is the run's safe end: surface, then done; outcome aborted.
TEST_F(StudioRunTest, AbortSurfacesTheVehicleThenEndsAborted) {
  ASSERT_TRUE(runner_->start(request(20.0)).ok());
  ASSERT_TRUE(wait_for([&] { return depth() > 1.0; }, 60s)) << "the vehicle never dived";
  runner_->abort();
  ASSERT_TRUE(ended(120s));
  const json end = hub_.snapshot()["ended"];
  EXPECT_EQ("aborted", end["outcome"]) << end.dump();
  EXPECT_EQ("studio", end["stopped_by"]);
  EXPECT_EQ("abort", end["stop"]);
  EXPECT_TRUE(end["surfaced"].get<bool>()) << end.dump();
  ASSERT_TRUE(end["final_depth_m"].is_number()) << end.dump();
  EXPECT_LT(end["final_depth_m"].get<double>(), surfaced_depth_m()) << end.dump();
  EXPECT_FALSE(end["phase"].get<std::string>().empty()) << end.dump();
  // The log says the same.
  ASSERT_EQ(1u, logs().size());
  const auto log = lines(logs()[0]);
  ASSERT_FALSE(log.empty());
  const json& mission_end = log.back();
  EXPECT_EQ("mission_end", mission_end["event"]);
  EXPECT_EQ("aborted", mission_end["outcome"]);
  EXPECT_EQ("abort", mission_end["stop"]);
  EXPECT_TRUE(mission_end["safe_end"]["surfaced"].get<bool>()) << mission_end.dump();
  // Issue 39: the run panel said 12.5 s, the replay 20.7 s (the end of the
  // surfacing). Both say the run's end now, and when the mission ended.
  EXPECT_NEAR(mission_end["sim_time"].get<double>(), end["t"].get<double>(), 1e-6) << end.dump();
  EXPECT_NEAR(mission_end["mission_sim_time"].get<double>(), end["mission_t"].get<double>(), 1e-6) << end.dump();
  EXPECT_LT(end["mission_t"].get<double>(), end["t"].get<double>()) << "the safe end took time";
  std::ifstream in(logs()[0]);
  const auto replayed = studio::replay_from_log(std::string((std::istreambuf_iterator<char>(in)), {}));
  ASSERT_TRUE(replayed.ok());
  const json& replay_end = replayed.value()["events"].back()["data"];
  EXPECT_NEAR(end["t"].get<double>(), replay_end["t"].get<double>(), 1e-6) << replay_end.dump();
  EXPECT_NEAR(end["mission_t"].get<double>(), replay_end["mission_t"].get<double>(), 1e-6) << replay_end.dump();
  for (const auto& l : log) {
    if (l["event"] == "vehicle_final") {
      EXPECT_LT(std::stod(l["depth_m"].dump()), surfaced_depth_m()) << l.dump();
    }
  }
}

// The studio closing (Ctrl-C on `strata studio`) asked the run to stop and
// then asked again from the runner's destructor: the second request cut the
// safe end short, leaving the vehicle under water.
TEST_F(StudioRunTest, ClosingTheStudioLetsTheSafeEndFinish) {
  ASSERT_TRUE(runner_->start(request(20.0)).ok());
  ASSERT_TRUE(wait_for([&] { return depth() > 1.0; }, 60s)) << "the vehicle never dived";
  runner_->abort();  // StudioServer::stop()
  runner_.reset();   // then the runner goes: it waits for the safe end
  const json end = hub_.snapshot()["ended"];
  ASSERT_FALSE(end.is_null());
  EXPECT_EQ("aborted", end["outcome"]) << end.dump();
  EXPECT_TRUE(end["surfaced"].get<bool>()) << end.dump();
  EXPECT_LT(end["final_depth_m"].get<double>(), surfaced_depth_m()) << end.dump();
}

// Stop is a hard stop: nothing more is sent to the vehicle.
TEST_F(StudioRunTest, StopIsAHardStopThatSendsNothingMore) {
  ASSERT_TRUE(runner_->start(request(20.0)).ok());
  ASSERT_TRUE(wait_for([&] { return depth() > 1.0; }, 60s)) << "the vehicle never dived";
  runner_->stop();
  ASSERT_TRUE(ended(60s));
  const json end = hub_.snapshot()["ended"];
  EXPECT_EQ("failed", end["outcome"]) << end.dump();
  EXPECT_EQ("hard", end["stop"]);
  EXPECT_EQ("studio", end["stopped_by"]);
  EXPECT_FALSE(end["surfaced"].get<bool>());
  EXPECT_NE(std::string::npos, end["reason"].get<std::string>().find("hard stop")) << end.dump();
  ASSERT_EQ(1u, logs().size());
  bool hard = false;
  for (const auto& l : lines(logs()[0])) {
    EXPECT_NE("emergency", l["event"]) << "a hard stop ran the safe end: " << l.dump();
    hard = hard || l["event"] == "hard_stop";
  }
  EXPECT_TRUE(hard);
}

TEST_F(StudioRunTest, EveryRunWritesItsLogInRunsBesideTheMissionAndItReplays) {
  ASSERT_TRUE(runner_->start(request(200.0)).ok());
  ASSERT_TRUE(ended());
  const json end = hub_.snapshot()["ended"];
  ASSERT_EQ(1u, logs().size());
  const std::string name = logs()[0].filename().string();
  EXPECT_TRUE(name.ends_with("Z-tank.coral.jsonl")) << name;
  EXPECT_EQ("tank/runs/" + name, end["log"]);
  std::ifstream in(logs()[0]);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  auto replay = studio::replay_from_log(text);
  ASSERT_TRUE(replay.ok());
  ASSERT_FALSE(replay.value()["events"].empty());
  EXPECT_EQ("run_end", replay.value()["events"].back()["event"]);
  EXPECT_EQ("completed", replay.value()["events"].back()["data"]["outcome"]);
  // A second run gets a log of its own.
  ASSERT_TRUE(wait_for([&] { return !runner_->running(); }, 10s));
  ASSERT_TRUE(runner_->start(request(200.0)).ok());
  ASSERT_TRUE(wait_for([&] { return !runner_->running(); }, 60s));
  EXPECT_EQ(2u, logs().size());
}

// The run's folder for logs may be a planted link: not followed.
TEST_F(StudioRunTest, ALinkPlantedAtRunsIsNotFollowed) {
  fs::create_directories(root() / "outside");
  fs::create_symlink("../../outside", studio() / "tank/runs");
  ASSERT_TRUE(fs::is_directory(studio() / "tank/runs"));
  ASSERT_TRUE(runner_->start(request(200.0)).ok());
  ASSERT_TRUE(ended());
  EXPECT_TRUE(fs::is_empty(root() / "outside"));
  EXPECT_EQ("", hub_.snapshot()["ended"]["log"]);
  EXPECT_EQ("completed", hub_.snapshot()["ended"]["outcome"]) << hub_.snapshot()["ended"].dump();
  bool said = false;
  const json reports = hub_.snapshot()["reports"];
  for (const auto& r : reports) {
    said = said || r["text"].get<std::string>().find("no mission log") != std::string::npos;
  }
  EXPECT_TRUE(said) << hub_.snapshot()["reports"].dump();
}

// Issue 17: a mission without scenarios/nominal.toml could not be run.
TEST_F(StudioRunTest, AMissionWithoutScenariosRunsTheBuiltInNominal) {
  fs::remove_all(studio() / "tank/scenarios");
  ASSERT_TRUE(runner_->start(request(200.0)).ok());
  ASSERT_TRUE(ended());
  EXPECT_EQ("completed", hub_.snapshot()["ended"]["outcome"]) << hub_.snapshot()["ended"].dump();
}

// The server checks a mission before the run reads it again: a file swapped
// for a link out in between is refused by the run itself (its reads go
// through the sandbox).
TEST_F(StudioRunTest, AnInputSwappedForALinkAfterTheCheckIsStillRefused) {
  fs::create_directories(root() / "outside");
  for (const char* swapped : {"setpoints.toml", "initialize.coral", "scenarios/nominal.toml"}) {
    SCOPED_TRACE(swapped);
    const fs::path victim = studio() / "tank" / swapped;
    const fs::path outside = root() / "outside" / fs::path(swapped).filename();
    fs::copy_file(victim, outside, fs::copy_options::overwrite_existing);
    fs::remove(victim);
    fs::create_symlink(outside, victim);
    ASSERT_TRUE(wait_for([&] { return !runner_->running(); }, 10s));
    ASSERT_TRUE(runner_->start(request(200.0)).ok());
    ASSERT_TRUE(wait_for([&] { return !runner_->running(); }, 60s));
    const json end = hub_.snapshot()["ended"];
    EXPECT_EQ("failed", end["outcome"]) << end.dump();
    EXPECT_NE(std::string::npos, end["reason"].get<std::string>().find("outside the studio's folder")) << end.dump();
    fs::remove(victim);
    fs::copy_file(outside, victim);
  }
}

TEST_F(StudioRunTest, AMissionThatFailsVerificationEndsWithTheReason) {
  fs::copy_file(fs::path(STRATA_SOURCE_DIR) / "tests/verify/exits_together.coral",
                studio() / "tank/exits_together.coral");
  ASSERT_TRUE(runner_->start(request(10.0, "tank/exits_together.coral")).ok());
  ASSERT_TRUE(ended(30s));
  EXPECT_NE(std::string::npos, hub_.snapshot()["ended"]["reason"].get<std::string>().find("fails verification"));
  // A run that never started leaves no log behind.
  EXPECT_TRUE(logs().empty());
}

// `.pl` missions run from the studio, on the process's PROLOG thread.
TEST_F(StudioRunTest, APrologMissionRuns) {
  ASSERT_TRUE(runner_->start(request(200.0, "tank/tank.pl")).ok());
  ASSERT_TRUE(ended(120s));
  const json snap = hub_.snapshot();
  EXPECT_EQ("completed", snap["ended"]["outcome"]) << snap["ended"].dump();
  EXPECT_GT(snap["telemetry"].size(), 10u);
  ASSERT_EQ(1u, logs().size());
  EXPECT_TRUE(logs()[0].filename().string().ends_with("Z-tank.pl.jsonl"));
}

}  // namespace
}  // namespace strata::cli::run_testing
