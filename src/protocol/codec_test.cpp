#include "protocol/codec.h"

#include <cmath>
#include <ostream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include <gtest/gtest.h>

namespace strata::protocol {

namespace {

// ---- examples ---------------------------------------------------------------

TEST(Codec, EncodesRequestsAsTheTableSays) {
  EXPECT_EQ("hello 1 strata 2\n", encode(make_hello(1, "strata")));  // the newest version
  EXPECT_EQ("exec 7 sleep 1\n", encode(make_exec(7, "sleep", {Value::integer(1)})));
  EXPECT_EQ("exec 8 setpoint 0.6 30\n", encode(make_exec(8, "setpoint", {Value::real(0.6), Value::integer(30)})));
  EXPECT_EQ("exec 9 log \"say \\\"hi\\\"\" 2.0\n",
            encode(make_exec(9, "log", {Value::string("say \"hi\""), Value::real(2.0)})));
  EXPECT_EQ("ask 10 depth_reached\n", encode(make_ask(10, "depth_reached")));
  EXPECT_EQ("ood 11 start_network\n", encode(make_ood(11, "start_network")));
  EXPECT_EQ("telemetry 12 2.0\n", encode(make_telemetry(12, 2.0)));
  EXPECT_EQ("ping 13\n", encode(make_ping(13)));
  EXPECT_EQ("bye 14\n", encode(make_bye(14)));
  EXPECT_EQ("advance 15\n", encode(make_advance(15)));
}

TEST(Codec, SpeaksVersionsOneAndTwo) {
  EXPECT_FALSE(speaks_version(0));
  EXPECT_TRUE(speaks_version(1));
  EXPECT_TRUE(speaks_version(2));
  EXPECT_FALSE(speaks_version(3));
  EXPECT_EQ("1 and 2", spoken_versions());
}

TEST(Codec, EncodesVehicleMessagesAsTheTableSays) {
  EXPECT_EQ("ok 1 phoenix 1 lockstep\n",
            encode(Welcome{1, "phoenix", 1, ClockMode::Lockstep, std::nullopt, std::nullopt}));
  EXPECT_EQ("ok 2 \"nps phoenix\" 1 wall\n",
            encode(Welcome{2, "nps phoenix", 1, ClockMode::Wall, std::nullopt, std::nullopt}));
  EXPECT_EQ("ok 3\n", encode(Ok{3, std::nullopt}));
  EXPECT_EQ("ok 3 12.5\n", encode(Ok{3, 12.5}));
  EXPECT_EQ("done 4 1 2.5\n", encode(Done{4, true, 2.5}));
  EXPECT_EQ("answer 5 0 0.1\n", encode(Answer{5, false, 0.1}));
  EXPECT_EQ("pong 6 12.5\n", encode(Pong{6, 12.5}));
  EXPECT_EQ("err 0 bad_line \"empty line\"\n", encode(Err{0, ErrorCode::BadLine, "empty line"}));
  EXPECT_EQ("hb 3.0\n", encode(Heartbeat{3.0}));
  EXPECT_EQ("event 4.25 \"watchdog tripped\"\n", encode(Event{4.25, "watchdog tripped"}));
  Telemetry t;
  t.sim_time_s = 12.5;
  t.depth_m = 1.02;
  t.rate_mps = 0.05;
  t.thrust_n = -3.25;
  t.extras = {{"mode", "diving"}, {"depth", "9"}, {"bad key", "1"}, {"x", "a b"}};
  EXPECT_EQ("tlm 12.5 depth=1.02 rate=0.05 thrust=-3.25 mode=diving\n", encode(t));
  t.setpoint_m = 0.6;
  t.heading_deg = 273.25;  // after setpoint, before the extras
  t.extras = {{"heading", "9"}};
  EXPECT_EQ("tlm 12.5 depth=1.02 rate=0.05 thrust=-3.25 setpoint=0.6 heading=273.25\n", encode(t));
}

TEST(Codec, DecodesRequests) {
  auto r = decode_request("exec 8 setpoint 0.6 30");
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(make_exec(8, "setpoint", {Value::real(0.6), Value::integer(30)}), r.value());
  EXPECT_EQ(make_ping(5), decode_request("   ping   5  ").value());
  EXPECT_EQ(make_ping(5), decode_request("ping 5\r\n").value());
  EXPECT_EQ(make_ping(5), decode_request("ping 5\n").value());
  EXPECT_EQ(make_ping(kMaxRequestId), decode_request("ping 9223372036854775807").value());
  EXPECT_EQ(make_exec(9, "say", {Value::string("a b"), Value::integer(-3), Value::real(1e3)}),
            decode_request(R"(exec 9 "say" "a b" -3 1e3)").value());
  Request hello = make_hello(1, "strata-tactical");
  hello.version = 2;  // the vehicle, not the decoder, refuses other versions
  EXPECT_EQ(hello, decode_request("hello 1 strata-tactical 2").value());
  EXPECT_EQ(make_telemetry(4, 0.0), decode_request("telemetry 4 0").value());
  EXPECT_EQ(make_telemetry(4, 100.0), decode_request("telemetry 4 100").value());
  EXPECT_EQ(make_advance(6), decode_request("advance 6").value());
}

TEST(Codec, DecodesVehicleMessages) {
  auto m = decode_vehicle_message("tlm 12.5 depth=1.02 fdepth=1 rate=0.05 thrust=-3.2 setpoint=1.5 mode=diving leak=0");
  ASSERT_TRUE(m.ok()) << m.error().message;
  const Telemetry& t = std::get<Telemetry>(m.value());
  EXPECT_EQ(12.5, t.sim_time_s);
  EXPECT_EQ(1.02, t.depth_m);
  EXPECT_EQ(1.0, t.filtered_depth_m);
  EXPECT_EQ(0.05, t.rate_mps);
  EXPECT_EQ(-3.2, t.thrust_n);
  EXPECT_EQ(1.5, t.setpoint_m);
  EXPECT_EQ((std::map<std::string, std::string>{{"leak", "0"}, {"mode", "diving"}}), t.extras);
  EXPECT_FALSE(t.heading_deg.has_value());
  auto h = decode_vehicle_message("tlm 3 heading=359.5 depth=0.5");
  ASSERT_TRUE(h.ok()) << h.error().message;
  EXPECT_EQ(359.5, std::get<Telemetry>(h.value()).heading_deg);
  EXPECT_EQ(0.5, std::get<Telemetry>(h.value()).depth_m);
  EXPECT_TRUE(std::get<Telemetry>(h.value()).extras.empty());

  EXPECT_EQ(VehicleMessage{Telemetry{}}, decode_vehicle_message("tlm 0").value());
  EXPECT_EQ(VehicleMessage(Welcome{1, "phoenix", 1, ClockMode::Wall, std::nullopt, std::nullopt}),
            decode_vehicle_message("ok 1 phoenix 1 wall").value());
  EXPECT_EQ(VehicleMessage(Err{0, ErrorCode::Busy, "another client"}),
            decode_vehicle_message("err 0 busy \"another client\"\r\n").value());
  // The sonar socket's port after the clock; other KEY=VALUE fields ignored.
  Welcome with_sonar{1, "phoenix", 1, ClockMode::Lockstep, 40123, std::nullopt};
  EXPECT_EQ("ok 1 phoenix 1 lockstep sonar=40123\n", encode(with_sonar));
  EXPECT_EQ(VehicleMessage(with_sonar), decode_vehicle_message("ok 1 phoenix 1 lockstep sonar=40123").value());
  EXPECT_EQ(VehicleMessage(with_sonar), decode_vehicle_message("ok 1 phoenix 1 lockstep future=x sonar=40123").value());
  EXPECT_EQ(ErrorCode::BadArgument, decode_vehicle_message("ok 1 phoenix 1 lockstep sonar=0").error().code);
  EXPECT_EQ(ErrorCode::BadArgument, decode_vehicle_message("ok 1 phoenix 1 lockstep sonar=70000").error().code);
  EXPECT_EQ(ErrorCode::BadArgument, decode_vehicle_message("ok 1 phoenix 1 lockstep junk").error().code);
  EXPECT_EQ(VehicleMessage(Event{2.0, "leak"}), decode_vehicle_message("event 2 leak").value());
  EXPECT_EQ(std::optional<RequestId>(4), reply_id(decode_vehicle_message("done 4 1 0.0").value()));
  EXPECT_EQ(std::nullopt, reply_id(decode_vehicle_message("hb 1").value()));
}

// ---- rejections ---------------------------------------------------------------

struct Rejection {
  std::string line;
  ErrorCode code;
  RequestId id;
};

std::string long_line(std::string_view start, std::size_t bytes) {
  std::string line(start);
  line += " \"";
  line.append(bytes - line.size() - 1, 'x');
  line += '"';
  return line;
}

void expect_rejected(const Rejection& r, const DecodeError& e) {
  EXPECT_EQ(code_name(r.code), code_name(e.code)) << r.line << " -> " << e.message;
  EXPECT_EQ(r.id, e.id) << r.line << " -> " << e.message;
  EXPECT_FALSE(e.message.empty());
}

TEST(Codec, RejectsMalformedRequestsWithTheCodeToAnswer) {
  std::string fields = "exec 21 f";
  for (std::size_t i = 3; i <= kMaxFields; ++i) fields += " 1";
  const std::vector<Rejection> cases = {
      {"", ErrorCode::BadLine, 0},
      {"   ", ErrorCode::BadLine, 0},
      {"\n", ErrorCode::BadLine, 0},
      {"fly 3", ErrorCode::UnknownVerb, 3},
      {"fly", ErrorCode::UnknownVerb, 0},
      {"EXEC 3 sleep 1", ErrorCode::UnknownVerb, 3},
      {"\"exec\" 3 sleep 1", ErrorCode::UnknownVerb, 0},
      {"hb 3.0", ErrorCode::UnknownVerb, 0},
      {"exec", ErrorCode::BadLine, 0},
      {"ping 0", ErrorCode::BadLine, 0},
      {"ping 9223372036854775808", ErrorCode::BadLine, 0},
      {"ping 99999999999999999999999", ErrorCode::BadLine, 0},
      {"ping abc", ErrorCode::BadLine, 0},
      {"ping -1", ErrorCode::BadLine, 0},
      {"ping 1.5", ErrorCode::BadLine, 0},
      {"ping \"1\"", ErrorCode::BadLine, 0},
      {R"(exec 4 log "a\qb")", ErrorCode::BadLine, 4},
      {R"(exec 5 log "abc)", ErrorCode::BadLine, 5},
      {R"(exec 5 log "abc"def)", ErrorCode::BadLine, 5},
      {"exec 6 sleep 1\x01", ErrorCode::BadLine, 6},
      {"exec 6 say \"\xc3\xa9\"", ErrorCode::BadLine, 6},
      {"exec\t7 sleep 1", ErrorCode::BadLine, 0},
      {"exec 7 sleep 1\r", ErrorCode::BadLine, 7},
      {"exec 7 sleep 1\n\n", ErrorCode::BadLine, 7},
      {"exec 7 sleep #1", ErrorCode::BadLine, 7},
      {fields, ErrorCode::BadLine, 21},
      {"exec 8 setpoint nan 30", ErrorCode::BadArgument, 8},
      {"exec 8 setpoint inf 30", ErrorCode::BadArgument, 8},
      {"exec 8 setpoint -inf 30", ErrorCode::BadArgument, 8},
      {"exec 8 setpoint 1e999 30", ErrorCode::BadArgument, 8},
      {"exec 8 sleep 9223372036854775808", ErrorCode::BadArgument, 8},
      {"exec 8 goto north", ErrorCode::BadArgument, 8},
      {"exec 8", ErrorCode::BadArgument, 8},
      {"exec 8 \"\"", ErrorCode::BadArgument, 8},
      {"ask 8", ErrorCode::BadArgument, 8},
      {"ood 8", ErrorCode::BadArgument, 8},
      {"ping 9 extra", ErrorCode::BadArgument, 9},
      {"bye 9 now", ErrorCode::BadArgument, 9},
      {"advance 9 1 2", ErrorCode::BadArgument, 9},
      {"advance 9 -1", ErrorCode::BadArgument, 9},
      {"advance", ErrorCode::BadLine, 0},
      {"hello 1 strata", ErrorCode::BadArgument, 1},
      {"hello 1 strata 1 x", ErrorCode::BadArgument, 1},
      {"hello 1 strata 0", ErrorCode::BadArgument, 1},
      {"hello 1 strata one", ErrorCode::BadArgument, 1},
      {"hello 1 strata 1.0", ErrorCode::BadArgument, 1},
      {"hello 1 \"\" 1", ErrorCode::BadArgument, 1},
      {"telemetry 2", ErrorCode::BadArgument, 2},
      {"telemetry 2 -1", ErrorCode::BadArgument, 2},
      {"telemetry 2 101", ErrorCode::BadArgument, 2},
      {"telemetry 2 fast", ErrorCode::BadArgument, 2},
      {"telemetry 2 \"5\"", ErrorCode::BadArgument, 2},
      {long_line("exec 31 say", kMaxLineBytes), ErrorCode::TooLong, 31},
      {long_line("exec 32 say", kMaxLineBytes - 1) + "\r\n", ErrorCode::TooLong, 32},
  };
  for (const Rejection& r : cases) {
    auto d = decode_request(r.line);
    ASSERT_FALSE(d.ok()) << r.line;
    expect_rejected(r, d.error());
  }
  // Right at the limit is fine, with either terminator.
  EXPECT_TRUE(decode_request(long_line("exec 33 say", kMaxLineBytes - 1)).ok());
  EXPECT_TRUE(decode_request(long_line("exec 33 say", kMaxLineBytes - 2) + "\r\n").ok());
}

TEST(Codec, RejectsMalformedVehicleMessages) {
  const std::vector<Rejection> cases = {
      {"", ErrorCode::BadLine, 0},
      {"ok", ErrorCode::BadLine, 0},
      {"ok 0", ErrorCode::BadLine, 0},
      {"ok 3 phoenix", ErrorCode::BadArgument, 3},
      {"ok 3 phoenix 1 fast", ErrorCode::BadArgument, 3},
      {"ok 3 phoenix 0 wall", ErrorCode::BadArgument, 3},
      {"done 3 2 0.0", ErrorCode::BadArgument, 3},
      {"done 3 yes 0.0", ErrorCode::BadArgument, 3},
      {"done 3 \"1\" 0.0", ErrorCode::BadArgument, 3},
      {"done 3 1", ErrorCode::BadArgument, 3},
      {"done 3 1 nan", ErrorCode::BadArgument, 3},
      {"answer 4", ErrorCode::BadArgument, 4},
      {"answer 4 1 1.0 1", ErrorCode::BadArgument, 4},
      {"pong 5 nan", ErrorCode::BadArgument, 5},
      {"pong 5 -1.0", ErrorCode::BadArgument, 5},
      {"err 0 weird \"x\"", ErrorCode::BadArgument, 0},
      {"err 6 failed", ErrorCode::BadArgument, 6},
      {"err -1 failed \"x\"", ErrorCode::BadLine, 0},
      {"welcome 7", ErrorCode::UnknownVerb, 7},
      {"tlm", ErrorCode::BadArgument, 0},
      {"tlm -1", ErrorCode::BadArgument, 0},
      {"tlm 1 depth", ErrorCode::BadArgument, 0},
      {"tlm 1 depth=x", ErrorCode::BadArgument, 0},
      {"tlm 1 depth=nan", ErrorCode::BadArgument, 0},
      {"tlm 1 depth=1 depth=2", ErrorCode::BadArgument, 0},
      {"tlm 1 heading=north", ErrorCode::BadArgument, 0},
      {"tlm 1 mode=a mode=b", ErrorCode::BadArgument, 0},
      {"tlm 1 =3", ErrorCode::BadArgument, 0},
      {"tlm 1 9x=3", ErrorCode::BadArgument, 0},
      {"tlm 1 depth=", ErrorCode::BadArgument, 0},
      {"tlm 1 \"depth=1\"", ErrorCode::BadArgument, 0},
      {"hb", ErrorCode::BadArgument, 0},
      {"hb 1 2", ErrorCode::BadArgument, 0},
      {"hb inf", ErrorCode::BadArgument, 0},
      {"event 1", ErrorCode::BadArgument, 0},
      {"event 1 \"a\\x\"", ErrorCode::BadLine, 0},
      {long_line("event 1.0", kMaxLineBytes), ErrorCode::TooLong, 0},
  };
  for (const Rejection& r : cases) {
    auto d = decode_vehicle_message(r.line);
    ASSERT_FALSE(d.ok()) << r.line;
    expect_rejected(r, d.error());
  }
}

TEST(Codec, ErrorsConvertForBothChannels) {
  DecodeError e = decode_request("ping 4 5").error();
  EXPECT_EQ("err 4 bad_argument \"'ping' takes ID only (3 fields given)\"\n", encode(to_err(e)));
  core::Error c = e.to_core();
  EXPECT_EQ(core::ErrorCode::Protocol, c.code);
  EXPECT_EQ("bad_argument: 'ping' takes ID only (3 fields given)", c.message);
  core::Result<Request> r = decode_request("ping 4").to_core();
  EXPECT_TRUE(r.ok());
}

TEST(Codec, PeekIdReadsTheSecondField) {
  EXPECT_EQ(12u, peek_id("exec 12 \"unterminated"));
  EXPECT_EQ(0u, peek_id("exec twelve"));
  EXPECT_EQ(0u, peek_id(""));
}

TEST(Codec, LongFreeTextIsCutToFitTheLine) {
  std::string text(5000, '"');
  std::string line = encode(Err{kMaxRequestId, ErrorCode::UnknownFunction, text});
  EXPECT_LE(line.size(), kMaxLineBytes);
  EXPECT_GE(line.size(), kMaxLineBytes - 1);  // an escape is 2 bytes
  auto back = decode_vehicle_message(line);
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_TRUE(std::get<Err>(back.value()).message.ends_with("\"..."));
}

// Lockstep's clock (docs/protocol.md §8): an advance may name the latest time
// to step to, its ok then says the vehicle's time, and the welcome says the
// time at the hello.
TEST(Codec, ABoundedAdvanceAndItsTimedOk) {
  EXPECT_EQ("advance 4 12.5\n", encode(make_advance(4, 12.5)));
  EXPECT_EQ("advance 4\n", encode(make_advance(4)));
  auto bounded = decode_request("advance 4 12.5");
  ASSERT_TRUE(bounded.ok()) << bounded.error().message;
  EXPECT_EQ(std::optional<double>(12.5), bounded.value().until_s);
  EXPECT_FALSE(decode_request("advance 4").value().until_s.has_value());
  for (const char* bad : {"advance 4 -1", "advance 4 soon", "advance 4 nan", "advance 4 \"3\"", "advance 4 1 2"}) {
    auto r = decode_request(bad);
    ASSERT_FALSE(r.ok()) << bad;
    EXPECT_EQ(4u, r.error().id) << bad;
  }
  EXPECT_EQ(VehicleMessage(Ok{7, 3.25}), decode_vehicle_message("ok 7 3.25").value());
  EXPECT_FALSE(decode_vehicle_message("ok 7 -3").ok());
  EXPECT_FALSE(decode_vehicle_message("ok 7 phoenix 2").ok());
  Welcome timed{1, "phoenix", 2, ClockMode::Lockstep, 40123, 6.5};
  EXPECT_EQ("ok 1 phoenix 2 lockstep sonar=40123 time=6.5\n", encode(timed));
  EXPECT_EQ(VehicleMessage(timed), decode_vehicle_message("ok 1 phoenix 2 lockstep sonar=40123 time=6.5").value());
  EXPECT_FALSE(decode_vehicle_message("ok 1 phoenix 2 lockstep time=-1").ok());
  EXPECT_FALSE(decode_vehicle_message("ok 1 phoenix 2 lockstep time=later").ok());
}

}  // namespace
}  // namespace strata::protocol
