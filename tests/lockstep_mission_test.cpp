// A CORAL mission with two branches in flight at once (issue 15), run
// in-process through the real stack: CoralEngine -> TacticalLevel ->
// VehicleLink -> TCP loopback -> VehicleServer. Lockstep is the wall clock
// made fast: the branches share simulated time, the run is deterministic,
// and the wall clock (at speed 20) makes the same calls in the same order,
// none of them earlier than lockstep's by more than a cycle.
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "coral/test_support.h"
#include "strategic/coral_engine.h"
#include "strategic/log_observer.h"
#include "strategic/tactics.h"
#include "tactical/catalogue.h"
#include "tactical/mission_log.h"
#include "tactical/tactical_level.h"
#include "tactical/test_rig.h"

namespace strata {
namespace {

using namespace std::chrono_literals;

// Branch A sleeps 5 s; branch B asks, sleeps 2 s; when both are done the
// mission asks once more and ends.
constexpr const char* kTwoBranches = R"(
mission two_branches {
  place begin = 1;
  place a, b, a_slept, filter_off, filter_on, b_slept, healthy, problem;
  exit done, failed;
  transition fork      { wait { begin } signal { a, b } }
  transition a_sleep   { wait { a } action { TACTIC(EXEC, sleep(5), a_slept) } }
  transition b_ask     { wait { b } action { TACTIC(ASK, depth_filter_off, filter_off, filter_on) } }
  transition b_sleep   { wait { filter_off } action { TACTIC(EXEC, sleep(2), b_slept) } }
  transition b_odd     { wait { filter_on } signal { failed } }
  transition join      { wait { a_slept, b_slept } action { TACTIC(ASK, system_problem, problem, healthy) } }
  transition all_well  { wait { healthy } signal { done } }
  transition unwell    { wait { problem } signal { failed } }
}
)";

struct Call {
  std::string primitive;
  bool value = false;
  double sim_time_s = 0.0;  // of its reply
};

// The Tactical level behind the Strategic interface, noting each call's
// outcome with the time of its own reply, in completion order.
class RecordingTactics final : public strategic::Tactics {
 public:
  explicit RecordingTactics(tactical::TacticalLevel& level) : level_(level) {}
  void call(std::string_view name, std::vector<tactical::Value> args, tactical::CallHandler done) override {
    level_.call(name, std::move(args),
                [this, name = std::string(name), done = std::move(done)](tactical::CallResult r) {
                  EXPECT_TRUE(r.ok()) << name << ": " << r.error().message;
                  if (r.ok()) calls.push_back({name, r.value().value, r.value().sim_time_s});
                  done(std::move(r));
                });
  }
  double sim_time_s() const override { return level_.sim_time_s(); }
  std::vector<Call> calls;

 private:
  tactical::TacticalLevel& level_;
};

struct MissionRun {
  std::optional<strategic::MissionResult> result;
  std::vector<Call> calls;
  std::string log;  // the mission log, wall_* fields stripped
};

MissionRun run_two_branches(protocol::ClockMode clock, int protocol_version = protocol::kProtocolVersion) {
  MissionRun run;
  auto compiled = coral::testing::compile_text(kTwoBranches);
  EXPECT_TRUE(compiled->program) << ::testing::PrintToString(compiled->kinds());
  if (!compiled->program) return run;
  tactical::testing::Rig rig(vehicle::Scenario::nominal(), clock);  // wall: speed 20
  tactical::LinkOptions o;
  o.protocol_version = protocol_version;
  auto link = rig.connect(o);
  std::ostringstream log_text;
  auto log = tactical::MissionLog::to_stream(
      log_text, tactical::RunInfo{"test", "two_branches", "", "", "", "nominal", 1,
                                  clock == protocol::ClockMode::Lockstep ? "lockstep" : "wall"});
  EXPECT_TRUE(log.ok());
  tactical::Catalogue catalogue = tactical::Catalogue::builtin();
  tactical::TacticalLevel level(rig.io, catalogue, link, nullptr, &log.value());
  // On the wall clock a sleep takes its simulated time over the speed.
  level.set_wall_seconds_per_sim_second(clock == protocol::ClockMode::Wall ? 1.0 / 20.0 : 1.0);
  RecordingTactics tactics(level);
  strategic::CoralEngine engine(*compiled->program, tactics);
  strategic::LogObserver observer(log.value());
  engine.add_observer(observer);
  engine.start([&](const strategic::MissionResult& r) { run.result = r; });
  EXPECT_TRUE(tactical::testing::run_until(
      rig.io, [&] { return run.result.has_value(); }, 10000ms));
  link->close();
  run.calls = tactics.calls;
  run.log = tactical::strip_wall_fields_from_log(log_text.str());
  return run;
}

std::string describe(const std::vector<Call>& calls) {
  std::string out;
  for (const auto& c : calls)
    out += fmt::format("  {} -> {} at {:.3f} s\n", c.primitive, c.value ? 1 : 0, c.sim_time_s);
  return out;
}

// (a) at mission level: the ask of branch B is answered in the cycle after
// it was sent, while branch A's sleep(5) runs.
TEST(LockstepMission, TwoBranchesShareSimulatedTime) {
  MissionRun run = run_two_branches(protocol::ClockMode::Lockstep);
  ASSERT_TRUE(run.result);
  EXPECT_EQ(strategic::Outcome::Completed, run.result->outcome) << run.result->reason;
  ASSERT_EQ(4u, run.calls.size()) << describe(run.calls);
  EXPECT_EQ("depth_filter_off", run.calls[0].primitive);
  EXPECT_DOUBLE_EQ(0.1, run.calls[0].sim_time_s);
  EXPECT_EQ("sleep", run.calls[1].primitive);  // branch B's, sent at 0.1 s
  EXPECT_DOUBLE_EQ(2.1, run.calls[1].sim_time_s);
  EXPECT_EQ("sleep", run.calls[2].primitive);  // branch A's, sent at 0 s
  EXPECT_DOUBLE_EQ(5.0, run.calls[2].sim_time_s);
  EXPECT_EQ("system_problem", run.calls[3].primitive);
  EXPECT_DOUBLE_EQ(5.1, run.calls[3].sim_time_s);
}

// What issue 15 reported, kept as protocol 1's documented behaviour: each
// request moves time itself, so branch B's ask waits for branch A's sleep.
TEST(LockstepMission, ProtocolOneServesTheBranchesOneAfterTheOther) {
  MissionRun run = run_two_branches(protocol::ClockMode::Lockstep, 1);
  ASSERT_TRUE(run.result);
  EXPECT_EQ(strategic::Outcome::Completed, run.result->outcome) << run.result->reason;
  ASSERT_EQ(4u, run.calls.size()) << describe(run.calls);
  EXPECT_EQ("sleep", run.calls[0].primitive);
  EXPECT_DOUBLE_EQ(5.0, run.calls[0].sim_time_s);
  EXPECT_EQ("depth_filter_off", run.calls[1].primitive);
  EXPECT_DOUBLE_EQ(5.1, run.calls[1].sim_time_s);
}

// (b) Deterministic: the same mission twice logs the same bytes (wall_*
// fields aside), concurrency included.
TEST(LockstepMission, TheSameMissionTwiceLogsTheSame) {
  MissionRun first = run_two_branches(protocol::ClockMode::Lockstep);
  MissionRun second = run_two_branches(protocol::ClockMode::Lockstep);
  ASSERT_FALSE(first.log.empty());
  EXPECT_NE(std::string::npos, first.log.find("\"event\":\"fire\"")) << first.log;
  EXPECT_EQ(first.log, second.log);
}

// (c) Lockstep is the wall clock made fast: the same calls in the same
// order with the same answers, and no reply on the wall clock earlier than
// a cycle (0.1 s) before lockstep's. How much later it may come depends on
// the machine's load (a reply late by 5 ms of wall time is 0.1 s of
// simulated time at speed 20), so it is not bounded here: it once failed a
// run at a load of 6, 0.2 s apart.
TEST(LockstepMission, LockstepAndTheWallClockAgree) {
  MissionRun lockstep = run_two_branches(protocol::ClockMode::Lockstep);
  MissionRun wall = run_two_branches(protocol::ClockMode::Wall);
  ASSERT_TRUE(lockstep.result && wall.result);
  EXPECT_EQ(strategic::Outcome::Completed, wall.result->outcome) << wall.result->reason;
  ASSERT_EQ(lockstep.calls.size(), wall.calls.size()) << "lockstep:\n"
                                                      << describe(lockstep.calls) << "wall:\n"
                                                      << describe(wall.calls);
  for (std::size_t i = 0; i < lockstep.calls.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(lockstep.calls[i].primitive, wall.calls[i].primitive);
    EXPECT_EQ(lockstep.calls[i].value, wall.calls[i].value);
    EXPECT_GE(wall.calls[i].sim_time_s, lockstep.calls[i].sim_time_s - 0.1 - 1e-6)
        << "lockstep:\n"
        << describe(lockstep.calls) << "wall:\n"
        << describe(wall.calls);
  }
}

}  // namespace
}  // namespace strata
