// The Tactical level against a real `strata vehicle` process on a free
// loopback port: what a user runs, not an in-process stand-in.
#include <asio.hpp>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "support/child_process.h"
#include "tactical/tactical_level.h"
#include "tactical/test_rig.h"

namespace strata::tactical {
namespace {

using strata::testing::ChildProcess;
using testing::run_until;
using namespace std::chrono_literals;

struct VehicleProcess {
  explicit VehicleProcess(std::vector<std::string> extra = {}) {
    std::vector<std::string> argv = {STRATA_BINARY, "vehicle", "--listen", "0"};
    argv.insert(argv.end(), extra.begin(), extra.end());
    child = std::make_unique<ChildProcess>(argv);
    auto line = child->first_line(10s);
    EXPECT_TRUE(line.has_value()) << "strata vehicle printed no address";
    if (line) port = static_cast<std::uint16_t>(std::stoi(line->substr(line->rfind(':') + 1)));
  }
  std::unique_ptr<ChildProcess> child;
  std::uint16_t port = 0;
};

std::shared_ptr<VehicleLink> connect(asio::io_context& io, std::uint16_t port,
                                     std::optional<core::Result<protocol::Welcome>>& welcome, int reconnects = 0) {
  LinkOptions o;
  o.port = port;
  o.reply_timeout = 2000ms;
  o.reconnect_attempts = reconnects;
  o.reconnect_delay = 50ms;
  auto link = VehicleLink::create(io, o);
  link->connect([&](core::Result<protocol::Welcome> r) { welcome = std::move(r); });
  EXPECT_TRUE(run_until(io, [&] { return welcome.has_value(); }));
  return link;
}

CallResult call(asio::io_context& io, TacticalLevel& t, std::string_view name, std::vector<Value> args = {}) {
  std::optional<CallResult> out;
  t.call(name, std::move(args), [&](CallResult r) { out = std::move(r); });
  EXPECT_TRUE(run_until(io, [&] { return out.has_value(); }));
  if (!out) return CallError{CallError::Kind::TimedOut, std::nullopt, "no outcome within the test's bound"};
  return std::move(*out);
}

TEST(VehicleProcess, EveryPrimitiveOfTheCatalogueIsAnswered) {
  VehicleProcess v;
  asio::io_context io;
  std::optional<core::Result<protocol::Welcome>> welcome;
  auto link = connect(io, v.port, welcome);
  ASSERT_TRUE(welcome && welcome->ok());
  EXPECT_EQ("phoenix-sim", welcome->value().vehicle_name);
  // The tank's setpoints and a waypoint inside the tank, for next_waypoint.
  std::ifstream in(std::string(STRATA_SOURCE_DIR) + "/missions/tank/setpoints.toml");
  std::stringstream text;
  text << in.rdbuf() << "\n[[waypoint]]\nx_m = 5\ny_m = 4\n";
  auto data = MissionData::parse(text.str(), "setpoints.toml");
  ASSERT_TRUE(data.ok()) << data.error().message;
  DataCursor cursor(data.value());
  TacticalLevel t(io, Catalogue::builtin(), link, &cursor, nullptr);
  std::vector<std::string> answered;
  for (const auto& p : Catalogue::builtin().all()) {
    std::vector<Value> args;
    if (p.name == "sleep") args.push_back(Value::of(1.0));
    if (p.name == "heading") args.push_back(Value::of(90.0));
    if (p.name == "report") args.push_back(Value::of("hello"));
    if (p.name == "goto_depth") args.push_back(Value::of(1.0));
    if (p.name == "set_speed") args.push_back(Value::of(0.5));
    if (p.name == "set_sway") args.push_back(Value::of(0.1));
    if (p.name == "set_altitude_floor") args.push_back(Value::of(1.0));
    if (p.name == "goto_xy") args = {Value::of(6.0), Value::of(4.0)};
    if (p.name == "track") args = {Value::of(2.0), Value::of(4.0), Value::of(10.0), Value::of(4.0)};
    if (p.name == "set_timer") args.push_back(Value::of(2.0));
    if (p.name == "loiter") args = {Value::of(6.0), Value::of(4.0), Value::of(5.0)};
    if (p.name == "start_rows") {  // before next_row in the catalogue: one row, inside the tank
      args = {Value::of(2.0), Value::of(2.0), Value::of(90.0), Value::of(8.0), Value::of(2.0), Value::of(1.0)};
    }
    if (p.name == "shutdown_network") continue;  // last, below
    if (p.name == "next_row") {                  // start_rows came before the network: no pattern, refused as such
      auto refused = call(io, t, p.name, args);
      ASSERT_FALSE(refused.ok());
      EXPECT_NE(std::string::npos, refused.error().message.find("no row pattern (start_rows first)"));
      answered.push_back(p.name);
      continue;
    }
    auto r = call(io, t, p.name, args);
    EXPECT_TRUE(r.ok()) << p.name << ": " << (r.ok() ? "" : r.error().message);
    if (r.ok()) answered.push_back(p.name);
  }
  auto r = call(io, t, "shutdown_network");
  EXPECT_TRUE(r.ok() && r.value().value);
  EXPECT_EQ(Catalogue::builtin().all().size() - 1, answered.size());
  EXPECT_GT(t.sim_time_s(), 1.0);
}

TEST(VehicleProcess, ASecondClientIsRefusedWhileTheFirstKeepsControl) {
  VehicleProcess v;
  asio::io_context io;
  std::optional<core::Result<protocol::Welcome>> first_welcome, second_welcome;
  auto first = connect(io, v.port, first_welcome);
  ASSERT_TRUE(first_welcome && first_welcome->ok());
  auto second = connect(io, v.port, second_welcome);
  ASSERT_TRUE(second_welcome.has_value());
  ASSERT_FALSE(second_welcome->ok());
  EXPECT_NE(std::string::npos, second_welcome->error().message.find("busy"));
  TacticalLevel t(io, Catalogue::builtin(), first, nullptr, nullptr);
  EXPECT_TRUE(call(io, t, "depth_filter_off").ok());
}

TEST(VehicleProcess, AVehicleThatDiesMidRequestIsAClearErrorNotAHang) {
  VehicleProcess v;
  asio::io_context io;
  std::optional<core::Result<protocol::Welcome>> welcome;
  auto link = connect(io, v.port, welcome, /*reconnects=*/2);
  ASSERT_TRUE(welcome && welcome->ok());
  std::optional<core::Error> lost;
  link->on_lost([&](const core::Error& e) { lost = e; });
  TacticalLevel t(io, Catalogue::builtin(), link, nullptr, nullptr);
  std::optional<CallResult> out;
  t.call("sleep", {Value::of(3000.0)}, [&](CallResult r) { out = std::move(r); });
  v.child->kill_now();
  ASSERT_TRUE(run_until(
      io, [&] { return out.has_value() && lost.has_value(); }, 10s));
  ASSERT_FALSE(out->ok());
  EXPECT_EQ(CallError::Kind::LinkLost, out->error().kind) << out->error().message;
  EXPECT_NE(std::string::npos, out->error().message.find("sleep")) << out->error().message;
  auto after = call(io, t, "depth_reached");
  ASSERT_FALSE(after.ok());
  EXPECT_NE(std::string::npos, after.error().message.find("no link to the vehicle")) << after.error().message;
}

TEST(VehicleProcess, GarbageToTheVehicleGetsErrorLinesAndTheLinkLives) {
  VehicleProcess v;
  asio::io_context io;
  asio::ip::tcp::socket s(io);
  s.connect({asio::ip::make_address("127.0.0.1"), v.port});
  std::string junk = "hello 1 raw 1\n\x01\x02\x03\nexec\nexec 0 sleep 1\n" + std::string(3000, 'z') +
                     "\nexec 7 sleep \"x\n" + "ping 8\n";
  asio::write(s, asio::buffer(junk));
  std::string got;
  std::array<char, 4096> buf{};
  auto deadline = std::chrono::steady_clock::now() + 5s;
  while (got.find("pong 8") == std::string::npos && std::chrono::steady_clock::now() < deadline) {
    s.non_blocking(true);
    asio::error_code ec;
    auto n = s.read_some(asio::buffer(buf), ec);
    if (ec == asio::error::would_block) {
      std::this_thread::sleep_for(10ms);
      continue;
    }
    ASSERT_FALSE(ec) << ec.message();
    got.append(buf.data(), n);
  }
  EXPECT_NE(std::string::npos, got.find("ok 1 phoenix-sim 1 lockstep")) << got;
  EXPECT_NE(std::string::npos, got.find("err 0 bad_line")) << got;
  EXPECT_NE(std::string::npos, got.find("err 0 too_long")) << got;
  EXPECT_NE(std::string::npos, got.find("err 7 bad_line")) << got;
  EXPECT_NE(std::string::npos, got.find("pong 8 0")) << got;  // still serving
}

// Regression (issues 15, 39): a client that connected and never said hello
// held `strata vehicle` (issue 15), and while it was within its hello
// timeout a real controller was refused `busy` (issue 39). The controller
// is served at once; the silent client is refused when it takes the vehicle.
TEST(VehicleProcess, ASilentClientNeverBlocksARealController) {
  VehicleProcess v({"--hello-timeout", "600"});
  asio::io_context io;
  testing::LineClient silent(io, v.port);
  std::optional<core::Result<protocol::Welcome>> welcome;
  auto served = connect(io, v.port, welcome);
  ASSERT_TRUE(welcome && welcome->ok()) << (welcome ? welcome->error().message : "");
  EXPECT_EQ(protocol::kProtocolVersion, welcome->value().version);
  TacticalLevel t(io, Catalogue::builtin(), served, nullptr, nullptr);
  EXPECT_TRUE(call(io, t, "depth_filter_off").ok());
  ASSERT_TRUE(run_until(
      io,
      [&] {
        silent.poll();
        return silent.closed;
      },
      10s));
  ASSERT_EQ(1u, silent.lines.size());
  EXPECT_EQ("err 0 busy \"another client controls the vehicle\"", silent.lines[0]);
}

TEST(VehicleProcess, HelloWithAnUnsupportedVersionIsRefusedNamingTheVersionsSpoken) {
  VehicleProcess v;
  asio::io_context io;
  testing::LineClient c(io, v.port);
  c.say("hello 1 hand 99");
  ASSERT_TRUE(c.wait_for(io, "err 1", 10s));
  EXPECT_EQ("err 1 bad_argument \"protocol version 99 is not spoken here; this vehicle speaks 1 and 2\"", c.lines[0]);
  c.say("hello 2 hand 2");
  ASSERT_TRUE(c.wait_for(io, "ok 2", 10s));
  EXPECT_TRUE(c.lines[1].starts_with("ok 2 phoenix-sim 2 lockstep")) << c.lines[1];
}

}  // namespace
}  // namespace strata::tactical
