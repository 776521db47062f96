// The Tactical level's primitives against the real vehicle server, as the
// Strategic level will call them.
#include <sstream>

#include <fmt/format.h>

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
  CallResult call(std::string_view name, std::vector<Value> args = {}) {
    std::optional<CallResult> out;
    tactical.call(name, std::move(args), [&](CallResult r) { out = std::move(r); });
    EXPECT_TRUE(run_until(rig_.io, [&] { return out.has_value(); }));
    if (!out) return CallError{CallError::Kind::TimedOut, std::nullopt, "no outcome within the test's bound"};
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
  t.call("report", {Value::of("hello")}, [&](CallResult r) {
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
  EXPECT_TRUE(r.error().link_gone()) << r.error().message;
}

// A link that answers each request as the test says, from the event loop.
class ScriptedLink final : public ExecutionLink {
 public:
  using Answer = std::function<core::Result<protocol::VehicleMessage>(const protocol::Request&)>;
  ScriptedLink(asio::io_context& io, Answer answer) : io_(io), answer_(std::move(answer)) {}
  protocol::RequestId send(protocol::Request request, ReplyHandler handler, std::optional<std::chrono::milliseconds>,
                           std::optional<double>) override {
    request.id = next_id_++;
    asio::post(io_, [this, request, handler = std::move(handler)] { handler(answer_(request)); });
    return request.id;
  }
  bool connected() const override { return true; }
  std::chrono::milliseconds default_timeout() const override { return std::chrono::milliseconds(100); }
  std::optional<double> sim_time_s() const override { return std::nullopt; }
  void close() override {}
  void event(std::string text) {
    if (on_event_) on_event_(protocol::Event{0.5, std::move(text)});
  }

 private:
  asio::io_context& io_;
  Answer answer_;
  protocol::RequestId next_id_ = 1;
};

TEST(TacticalLevel, AnErrReplyIsRefusedWithTheVehiclesCode) {
  asio::io_context io;
  auto refusing = std::make_shared<ScriptedLink>(io, [](const protocol::Request& r) {
    return core::Result<protocol::VehicleMessage>(
        protocol::VehicleMessage(protocol::Err{r.id, protocol::ErrorCode::NotReady, "the watchdog tripped"}));
  });
  TacticalLevel t(io, Catalogue::builtin(), refusing, nullptr, nullptr);
  std::optional<CallResult> out;
  std::optional<CallRecord> record;
  t.on_call([&](const CallRecord& r) { record = r; });
  t.call("sleep", {Value::of(1.0)}, [&](CallResult r) { out = std::move(r); });
  io.run();
  ASSERT_TRUE(out && !out->ok());
  EXPECT_EQ(CallError::Kind::Refused, out->error().kind);
  EXPECT_EQ(protocol::ErrorCode::NotReady, out->error().vehicle_code);
  EXPECT_EQ("vehicle refused `exec sleep 1` (request 1): not_ready: the watchdog tripped", out->error().message);
  ASSERT_TRUE(record && record->error);
  EXPECT_EQ(CallError::Kind::Refused, record->error->kind);
  EXPECT_EQ(core::CallVerb::Exec, record->verb);
  EXPECT_FALSE(record->value.has_value());
}

TEST(TacticalLevel, ATimeoutIsTimedOutAndAClosedLinkIsLinkLost) {
  for (auto [code, kind] : {std::pair{core::ErrorCode::Timeout, CallError::Kind::TimedOut},
                            std::pair{core::ErrorCode::Closed, CallError::Kind::LinkLost},
                            std::pair{core::ErrorCode::Io, CallError::Kind::LinkLost},
                            std::pair{core::ErrorCode::Protocol, CallError::Kind::BadReply},
                            std::pair{core::ErrorCode::InvalidInput, CallError::Kind::Refused}}) {
    asio::io_context io;
    auto failing = std::make_shared<ScriptedLink>(io, [code = code](const protocol::Request&) {
      return core::Result<protocol::VehicleMessage>(core::make_error(code, "the link's words"));
    });
    TacticalLevel t(io, Catalogue::builtin(), failing, nullptr, nullptr);
    std::optional<CallResult> out;
    t.call("depth_reached", {}, [&](CallResult r) { out = std::move(r); });
    io.run();
    ASSERT_TRUE(out && !out->ok());
    EXPECT_EQ(kind, out->error().kind) << kind_name(out->error().kind);
    EXPECT_FALSE(out->error().vehicle_code.has_value());
    EXPECT_EQ("the link's words", out->error().message);
  }
}

TEST(CallError, ToCoreGivesTheCodeABoundaryExpects) {
  auto code = [](CallError::Kind k) { return CallError{k, std::nullopt, "m"}.to_core().code; };
  EXPECT_EQ(core::ErrorCode::Timeout, code(CallError::Kind::TimedOut));
  EXPECT_EQ(core::ErrorCode::Closed, code(CallError::Kind::LinkLost));
  EXPECT_EQ(core::ErrorCode::Protocol, code(CallError::Kind::Refused));
  EXPECT_EQ(core::ErrorCode::Protocol, code(CallError::Kind::BadReply));
  EXPECT_EQ(core::ErrorCode::InvalidInput, code(CallError::Kind::BadCall));
  EXPECT_EQ(core::ErrorCode::InvalidInput, code(CallError::Kind::Withheld));
  const CallError refused{CallError::Kind::Refused, std::nullopt, "m"};
  EXPECT_EQ("m", refused.to_core().message);
}

TEST(TacticalLevel, NoLinkIsLinkLost) {
  asio::io_context io;
  TacticalLevel t(io, Catalogue::builtin(), nullptr, nullptr, nullptr);
  std::optional<CallResult> out;
  t.call("depth_reached", {}, [&](CallResult r) { out = std::move(r); });
  io.run();
  ASSERT_TRUE(out && !out->ok());
  EXPECT_EQ(CallError::Kind::LinkLost, out->error().kind);
}

TEST(TacticalLevel, AnUnknownPrimitiveABadArgumentOrNoMissionDataIsABadCallNeverSent) {
  asio::io_context io;
  bool sent = false;
  auto link = std::make_shared<ScriptedLink>(io, [&](const protocol::Request& r) {
    sent = true;
    return core::Result<protocol::VehicleMessage>(protocol::VehicleMessage(protocol::Done{r.id, true, 1.0}));
  });
  TacticalLevel t(io, Catalogue::builtin(), link, nullptr, nullptr);
  std::vector<CallRecord> records;
  t.on_call([&](const CallRecord& r) { records.push_back(r); });
  std::vector<CallResult> outs;
  t.call("warp_drive", {}, [&](CallResult r) { outs.push_back(std::move(r)); });
  t.call("sleep", {Value::of("long")}, [&](CallResult r) { outs.push_back(std::move(r)); });
  t.call("next_setpt_data", {}, [&](CallResult r) { outs.push_back(std::move(r)); });
  io.run();
  ASSERT_EQ(3u, outs.size());
  for (const CallResult& r : outs) {
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(CallError::Kind::BadCall, r.error().kind) << r.error().message;
  }
  EXPECT_FALSE(sent);
  ASSERT_EQ(3u, records.size());
  EXPECT_FALSE(records[0].verb.has_value()) << "no primitive has the name";
  EXPECT_EQ(core::CallVerb::Exec, records[1].verb);
}

TEST(TacticalLevel, AReplyOfTheWrongKindIsABadReply) {
  asio::io_context io;
  auto link = std::make_shared<ScriptedLink>(io, [](const protocol::Request& r) {
    return core::Result<protocol::VehicleMessage>(protocol::VehicleMessage(protocol::Pong{r.id, 1.0}));
  });
  TacticalLevel t(io, Catalogue::builtin(), link, nullptr, nullptr);
  std::optional<CallResult> out;
  t.call("surface", {}, [&](CallResult r) { out = std::move(r); });
  io.run();
  ASSERT_TRUE(out && !out->ok());
  EXPECT_EQ(CallError::Kind::BadReply, out->error().kind);
}

TEST(TacticalLevel, AnExecAnsweredZeroCarriesWhatTheVehicleSaidMeanwhile) {
  asio::io_context io;
  std::shared_ptr<ScriptedLink> link;
  link = std::make_shared<ScriptedLink>(io, [&](const protocol::Request& r) {
    link->event(fmt::format("{} {} failed: depth filter is off", protocol::verb_name(r.verb), r.name));
    return core::Result<protocol::VehicleMessage>(protocol::VehicleMessage(protocol::Done{r.id, false, 1.0}));
  });
  TacticalLevel t(io, Catalogue::builtin(), link, nullptr, nullptr);
  std::vector<CallRecord> records;
  t.on_call([&](const CallRecord& r) { records.push_back(r); });
  t.call("submerge", {}, [](const CallResult&) {});
  io.run();
  ASSERT_EQ(1u, records.size());
  EXPECT_EQ(false, records[0].value);
  EXPECT_EQ("exec submerge failed: depth filter is off", records[0].vehicle_said);
}

TEST(TacticalLevel, AnEventBeforeTheCallIsNotItsReason) {
  asio::io_context io;
  auto link = std::make_shared<ScriptedLink>(io, [](const protocol::Request& r) {
    return core::Result<protocol::VehicleMessage>(protocol::VehicleMessage(protocol::Done{r.id, false, 1.0}));
  });
  TacticalLevel t(io, Catalogue::builtin(), link, nullptr, nullptr);
  link->event("13.0 s: at the surface; holding");
  std::vector<CallRecord> records;
  t.on_call([&](const CallRecord& r) { records.push_back(r); });
  t.call("submerge", {}, [](const CallResult&) {});
  io.run();
  ASSERT_EQ(1u, records.size());
  EXPECT_EQ("", records[0].vehicle_said);
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
    const std::vector<protocol::Value> args{protocol::Value::integer(1), protocol::Value::string("x")};
    EXPECT_EQ(args, r.args);
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

// The telemetry line is written without building a JSON value: its bytes
// are the line the log wrote from one ({"event","sim_time"}, then the fields).
TEST(TelemetryLogFields, TheLogLineIsTheJsonLineItReplaced) {
  protocol::Telemetry t;
  t.sim_time_s = 12.3000004;
  t.depth_m = -0.0412;
  t.filtered_depth_m = 1.5;
  t.rate_mps = 1e-7;
  t.thrust_n = 0.0;
  t.heading_deg = 359.99;
  t.extras = {{"x", "12.35"}, {"speed", "0.800"}, {"alt", "garbage"}};
  nlohmann::ordered_json j;
  j["event"] = "telemetry";
  j["sim_time"] = log_time(t.sim_time_s);
  const nlohmann::ordered_json fields = telemetry_log_fields(t);
  for (const auto& [k, v] : fields.items()) j[k] = v;
  EXPECT_EQ(j.dump() + "\n", telemetry_log_line(t).finish());
}

}  // namespace
}  // namespace strata::tactical
