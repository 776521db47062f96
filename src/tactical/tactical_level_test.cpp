// The Tactical level's primitives against the real vehicle server, as the
// Strategic level will call them.
#include <sstream>

#include <gtest/gtest.h>

#include "tactical/tactical_level.h"
#include "tactical/test_rig.h"

namespace strata::tactical {
namespace {

using testing::Rig;
using testing::run_until;

struct Mission {
  explicit Mission(Rig& rig)
      : data(MissionData::load(std::string(STRATA_SOURCE_DIR) + "/missions/tank/setpoints.toml").value()),
        cursor(data),
        log(MissionLog::to_stream(log_text, RunInfo{"test", "tank", "", "setpoints.toml", "", "nominal", 1}).value()),
        link(rig.connect()),
        tactical(rig.io, Catalogue::builtin(), link, &cursor, &log),
        rig_(rig) {}

  // Calls a primitive and waits for its outcome.
  core::Result<CallOutcome> call(std::string_view name, std::vector<Value> args = {}) {
    std::optional<core::Result<CallOutcome>> out;
    tactical.call(name, std::move(args), [&](core::Result<CallOutcome> r) { out = std::move(r); });
    EXPECT_TRUE(run_until(rig_.io, [&] { return out.has_value(); }));
    if (!out) return core::make_error(core::ErrorCode::Internal, "no outcome within the test's bound");
    return std::move(*out);
  }
  bool yes(std::string_view name, std::vector<Value> args = {}) {
    auto r = call(name, std::move(args));
    EXPECT_TRUE(r.ok()) << name << ": " << (r.ok() ? "" : r.error().message);
    return r.ok() && r.value().value;
  }

  // Paper Figure 10, execute_phase(2), step for step.
  bool phase2() {
    EXPECT_TRUE(yes("next_setpt_data"));
    if (yes("depth_filter_off")) {  // start_depth_filter
      EXPECT_TRUE(yes("start_depth_filter"));
      EXPECT_TRUE(yes("sleep", {Value::of(1.0)}));
    }
    EXPECT_TRUE(yes("submerge"));
    EXPECT_TRUE(yes("start_timer"));
    for (int i = 0; i < 600; ++i) {  // repeat, phase_completed(2)
      EXPECT_TRUE(yes("sleep", {Value::of(1.0)}));
      if (yes("depth_reached")) return true;
      if (yes("time_out") || yes("system_problem")) {
        EXPECT_TRUE(yes("surface"));
        for (int j = 0; j < 2000 && !yes("surface_reached"); ++j) {}
        return false;
      }
    }
    ADD_FAILURE() << "phase 2 did not end";
    return false;
  }

  std::ostringstream log_text;
  MissionData data;
  DataCursor cursor;
  MissionLog log;
  std::shared_ptr<VehicleLink> link;
  TacticalLevel tactical;
  Rig& rig_;
};

TEST(TacticalLevel, Figure10Phase2ReachesDepthInNominal) {
  Rig rig;
  Mission m(rig);
  ASSERT_TRUE(m.yes("start_network"));
  EXPECT_TRUE(m.phase2());
  EXPECT_NEAR(0.6, rig.sim.heave().depth_m, 0.1);  // the first setpoint
  EXPECT_FALSE(rig.sim.time_out());
}

TEST(TacticalLevel, Figure10Phase2TimesOutWithWeakThrusters) {
  auto scenario =
      vehicle::load_scenario(std::string(STRATA_SOURCE_DIR) + "/missions/tank/scenarios/weak_thrusters.toml");
  ASSERT_TRUE(scenario.ok());
  Rig rig(scenario.value());
  Mission m(rig);
  ASSERT_TRUE(m.yes("start_network"));
  EXPECT_FALSE(m.phase2());
  EXPECT_TRUE(rig.sim.time_out());
  EXPECT_TRUE(rig.sim.surface_reached());
  EXPECT_GE(m.tactical.sim_time_s(), 30.0);  // the setpoint's time limit ran out
}

TEST(TacticalLevel, EveryRequestAndReplyIsLoggedWithSimTime) {
  Rig rig;
  Mission m(rig);
  ASSERT_TRUE(m.yes("start_network"));
  ASSERT_TRUE(m.yes("next_setpt_data"));
  ASSERT_TRUE(m.yes("report", {Value::of("diving")}));
  std::istringstream lines(m.log_text.str());
  std::vector<nlohmann::json> events;
  for (std::string line; std::getline(lines, line);) events.push_back(nlohmann::json::parse(line));
  ASSERT_EQ(6u, events.size());
  EXPECT_EQ("run", events[0]["event"]);
  EXPECT_EQ("request", events[1]["event"]);
  EXPECT_EQ("ood start_network", events[1]["message"]);
  EXPECT_EQ("reply", events[2]["event"]);
  EXPECT_EQ(1, events[2]["result"]);
  EXPECT_DOUBLE_EQ(0.1, events[2]["sim_time"].get<double>());
  EXPECT_EQ("exec setpoint 0.6 30", events[3]["message"]);  // from setpoints.toml
  EXPECT_EQ("report", events[5]["event"]);
  EXPECT_EQ("diving", events[5]["text"]);
}

TEST(TacticalLevel, ErrorsAreOutcomesNotExceptions) {
  Rig rig;
  Mission m(rig);
  auto unknown = m.call("warp_drive");
  ASSERT_FALSE(unknown.ok());
  EXPECT_NE(std::string::npos, unknown.error().message.find("unknown primitive 'warp_drive'"));
  auto bad = m.call("sleep", {Value::of("long")});
  ASSERT_FALSE(bad.ok());
  // Three setpoints in the tank data; the fourth read is a clear error.
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(m.call("next_setpt_data").ok());
  auto past = m.call("next_setpt_data");
  ASSERT_FALSE(past.ok());
  EXPECT_NE(std::string::npos, past.error().message.find("3 setpoints")) << past.error().message;
  // A refused function (network not started) answers 0, not an error.
  auto refused = m.call("submerge");
  ASSERT_TRUE(refused.ok());
  EXPECT_FALSE(refused.value().value);
}

// Regression: without a link, REPORT answered inside call(), so an engine
// firing a REPORT re-entered itself.
TEST(TacticalLevel, OutcomesNeverArriveInsideCall) {
  asio::io_context io;
  TacticalLevel t(io, Catalogue::builtin(), nullptr, nullptr, nullptr);
  bool returned = false, early = false, answered = false;
  t.call("report", {Value::of("hello")}, [&](core::Result<CallOutcome> r) {
    early = !returned;
    answered = r.ok() && r.value().value;
  });
  returned = true;
  io.run();
  EXPECT_FALSE(early);
  EXPECT_TRUE(answered);
}

TEST(TacticalLevel, RequestsToAVanishedVehicleFailWithAReason) {
  Rig rig;
  Mission m(rig);
  rig.server->stop();
  auto r = m.call("depth_reached");
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(r.error().code == core::ErrorCode::Closed || r.error().code == core::ErrorCode::Timeout)
      << r.error().message;
}

TEST(ToRequest, EachCallVerbGoesOutAsItsOwnWireVerbAndReportNever) {
  EXPECT_EQ(protocol::Verb::Exec, wire_verb(core::CallVerb::Exec));
  EXPECT_EQ(protocol::Verb::Ask, wire_verb(core::CallVerb::Ask));
  EXPECT_EQ(protocol::Verb::Ood, wire_verb(core::CallVerb::Ood));
  EXPECT_FALSE(wire_verb(core::CallVerb::Report).has_value());
  for (core::CallVerb v : core::kCallVerbs) {
    if (v == core::CallVerb::Report) continue;
    RenderedCall call{v, "f", {Value::of(1.0), Value::of("x")}, 2.0};
    const protocol::Request r = to_request(call);
    EXPECT_EQ(core::call_verb_name(v), protocol::verb_name(r.verb)) << "the same word on both sides";
    EXPECT_EQ("f", r.name);
    EXPECT_EQ((std::vector<protocol::Value>{protocol::Value::integer(1), protocol::Value::string("x")}), r.args);
  }
}

TEST(TelemetryLogFields, OpenWaterAddsThePlaneAfterTheTankFields) {
  protocol::Telemetry t;
  t.depth_m = 2.0;
  t.heading_deg = 90.0;
  EXPECT_EQ(R"({"depth_m":2.0,"heading_deg":90.0})", telemetry_log_fields(t).dump());
  t.extras = {{"x", "12.35"},     {"y", "-3.00"},     {"true_x", "13.00"}, {"true_y", "-2.50"},
              {"pos_sd", "4.25"}, {"speed", "0.800"}, {"alt", "7.50"},     {"mode", "depth"}};
  EXPECT_EQ(R"({"depth_m":2.0,"heading_deg":90.0,"x_m":12.35,"y_m":-3.0,"true_x_m":13.0,"true_y_m":-2.5,)"
            R"("position_sd_m":4.25,"speed_mps":0.8,"altitude_m":7.5})",
            telemetry_log_fields(t).dump());
  t.extras = {{"x", "nan"}, {"y", "1e999"}, {"alt", "7.5m"}};  // garbage from a vehicle: left out
  EXPECT_EQ(R"({"depth_m":2.0,"heading_deg":90.0})", telemetry_log_fields(t).dump());
}

}  // namespace
}  // namespace strata::tactical
