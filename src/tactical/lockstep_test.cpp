// Lockstep with requests in flight together (protocol 2): the link sends
// `advance` once its caller is quiescent, and the vehicle moves every
// waiting request together, so concurrent calls share simulated time as on
// the wall clock. Against the real vehicle server in one process over
// loopback, and against a scripted stand-in where the bytes must arrive in
// a chosen way.
#include <chrono>
#include <optional>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include <asio.hpp>
#include <gtest/gtest.h>

#include "protocol/codec.h"
#include "tactical/tactical_level.h"
#include "tactical/test_rig.h"
#include "tactical/vehicle_link.h"

namespace strata::tactical {
namespace {

using namespace std::chrono_literals;
using protocol::Value;
using protocol::VehicleMessage;
using testing::Rig;
using testing::run_until;

double time_of(const VehicleMessage& m) {
  if (auto* d = std::get_if<protocol::Done>(&m)) return d->sim_time_s;
  if (auto* a = std::get_if<protocol::Answer>(&m)) return a->sim_time_s;
  return -1.0;
}

// (a) The case of issue 15: with `sleep 5` in flight, an ask is answered in
// the next cycle, not after the sleep.
TEST(Lockstep, AnAskSentWhileASleepRunsIsAnsweredInTheNextCycle) {
  Rig rig;
  auto link = rig.connect();
  ASSERT_TRUE(link->lockstep_barrier());
  std::vector<std::string> order;
  std::optional<double> slept, first_ask, second_ask;
  link->send(protocol::make_exec(0, "sleep", {Value::integer(5)}), [&](core::Result<VehicleMessage> r) {
    ASSERT_TRUE(r.ok()) << r.error().message;
    slept = time_of(r.value());
    order.push_back("sleep");
  });
  link->send(protocol::make_ask(0, "depth_filter_off"), [&](core::Result<VehicleMessage> r) {
    ASSERT_TRUE(r.ok()) << r.error().message;
    first_ask = time_of(r.value());
    order.push_back("ask");
    // Asked at 0.1 s, while the sleep runs: answered at 0.2 s.
    link->send(protocol::make_ask(0, "system_problem"), [&](core::Result<VehicleMessage> r2) {
      ASSERT_TRUE(r2.ok()) << r2.error().message;
      second_ask = time_of(r2.value());
      order.push_back("ask again");
    });
  });
  ASSERT_TRUE(run_until(rig.io, [&] { return slept && second_ask; }));
  EXPECT_DOUBLE_EQ(0.1, *first_ask);
  EXPECT_DOUBLE_EQ(0.2, *second_ask);
  EXPECT_DOUBLE_EQ(5.0, *slept);
  EXPECT_EQ((std::vector<std::string>{"ask", "ask again", "sleep"}), order);
  EXPECT_DOUBLE_EQ(5.0, rig.sim.time_s());
  EXPECT_EQ(3u, link->advances_sent());  // 0 -> 0.1, 0.1 -> 0.2, 0.2 -> 5.0
}

// The embedded vehicle of a run (run/session_start.cpp): the server and the
// link over a connected pair of local sockets, no port. The same protocol
// (hello, the lockstep barrier, a call); and when the vehicle closes its
// end, the link is lost at once: there is nothing to reconnect to, whatever
// LinkOptions::reconnect_attempts says (the link's comments: a lost link
// is otherwise told only once the reconnects have failed).
TEST(Lockstep, APairedLinkSpeaksTheProtocolAndIsLostWithoutReconnectingWhenClosed) {
  asio::io_context io;
  vehicle::Simulation sim(vehicle::default_params(), vehicle::Scenario::nominal());
  vehicle::ServerOptions so;
  so.clock = protocol::ClockMode::Lockstep;
  so.lockstep_silence_s = 0.0;
  vehicle::VehicleServer server(io, sim, so);
  asio::local::stream_protocol::socket ours(io), theirs(io);
  asio::error_code ec;
  asio::local::connect_pair(ours, theirs, ec);
  ASSERT_FALSE(ec) << ec.message();
  ASSERT_TRUE(server.start_paired(std::move(theirs)).ok());
  EXPECT_EQ(0, server.port()) << "no listening socket";

  LinkOptions options;
  options.reconnect_attempts = 2;
  options.reconnect_delay = std::chrono::minutes(10);  // a reconnect would outlast the test's bound
  auto link = VehicleLink::create(io, options);
  std::optional<core::Result<protocol::Welcome>> welcome;
  link->connect_paired(std::move(ours), [&](core::Result<protocol::Welcome> w) { welcome = std::move(w); });
  ASSERT_TRUE(run_until(io, [&] { return welcome.has_value(); }));
  ASSERT_TRUE(welcome->ok()) << welcome->error().message;
  EXPECT_EQ(protocol::ClockMode::Lockstep, welcome->value().clock);
  EXPECT_TRUE(link->lockstep_barrier());

  std::optional<core::Result<VehicleMessage>> reply;
  link->send(protocol::make_ask(0, "depth_filter_off"), [&](core::Result<VehicleMessage> r) { reply = std::move(r); });
  ASSERT_TRUE(run_until(io, [&] { return reply.has_value(); }));
  ASSERT_TRUE(reply->ok()) << reply->error().message;
  EXPECT_DOUBLE_EQ(0.1, time_of(reply->value()));
  EXPECT_NEAR(0.1, sim.time_s(), 1e-9);

  int lost = 0;
  link->on_lost([&](const core::Error&) { ++lost; });
  server.stop();
  ASSERT_TRUE(run_until(io, [&] { return lost > 0; })) << "the link waited to reconnect";
  EXPECT_EQ(1, lost);
  EXPECT_FALSE(link->connected());
}

// One call in flight at a time costs what it did in protocol 1: a cycle
// each, sleep its duration.
TEST(Lockstep, OneCallAtATimeCostsWhatItDidInProtocolOne) {
  Rig rig;
  auto link = rig.connect();
  ASSERT_TRUE(rig.call(*link, protocol::make_ood(0, "start_network")).ok());
  EXPECT_NEAR(0.1, rig.sim.time_s(), 1e-9);
  EXPECT_TRUE(rig.ask(*link, "depth_filter_off"));
  EXPECT_NEAR(0.2, rig.sim.time_s(), 1e-9);
  EXPECT_TRUE(rig.exec(*link, "sleep", {Value::integer(2)}));
  EXPECT_NEAR(2.2, rig.sim.time_s(), 1e-9);
  EXPECT_TRUE(rig.exec(*link, "sleep", {Value::integer(0)}));  // at least one cycle
  EXPECT_NEAR(2.3, rig.sim.time_s(), 1e-9);
}

// Two branches of calls driven from their replies, with telemetry; every
// line both ways, the welcome's random sonar port left out.
std::vector<std::string> concurrent_exchange() {
  std::vector<std::string> lines;
  LinkOptions o;
  o.tap = [&](bool sent, std::string_view line) {
    lines.push_back(
        std::regex_replace(std::string(sent ? "> " : "< ") + std::string(line), std::regex(" sonar=[0-9]+"), ""));
  };
  Rig rig;
  auto link = rig.connect(o);
  EXPECT_TRUE(rig.call(*link, protocol::make_telemetry(0, 2.0)).ok());
  EXPECT_TRUE(rig.call(*link, protocol::make_ood(0, "start_network")).ok());
  // Branch A dives: setpoint, filter, submerge, then sleeps 1 s at a time.
  // Branch B asks depth_reached and sleeps 0.3 s between asks; both end
  // after 6 turns.
  int a_turns = 0, b_turns = 0;
  std::function<void()> a_sleep = [&] {
    link->send(protocol::make_exec(0, "sleep", {Value::integer(1)}), [&](core::Result<VehicleMessage> r) {
      EXPECT_TRUE(r.ok());
      if (++a_turns < 6) a_sleep();
    });
  };
  std::function<void()> b_ask = [&] {
    link->send(protocol::make_ask(0, "depth_reached"), [&](core::Result<VehicleMessage> r) {
      EXPECT_TRUE(r.ok());
      if (++b_turns >= 6) return;
      link->send(protocol::make_exec(0, "sleep", {Value::real(0.3)}), [&](core::Result<VehicleMessage>) { b_ask(); });
    });
  };
  link->send(protocol::make_exec(0, "setpoint", {Value::real(1.0), Value::integer(60)}),
             [&](core::Result<VehicleMessage>) {
               link->send(protocol::make_exec(0, "start_depth_filter"), [&](core::Result<VehicleMessage>) {
                 link->send(protocol::make_exec(0, "submerge"), [&](core::Result<VehicleMessage>) { a_sleep(); });
               });
             });
  b_ask();
  EXPECT_TRUE(run_until(rig.io, [&] { return a_turns == 6 && b_turns == 6; }));
  return lines;
}

// (b) The same concurrent exchange twice: the same lines, byte for byte.
TEST(Lockstep, TheSameConcurrentExchangeTwiceGivesTheSameLines) {
  const auto first = concurrent_exchange();
  const auto second = concurrent_exchange();
  ASSERT_GT(first.size(), 40u);
  EXPECT_EQ(first, second);
  // And it was concurrent: an ask answered while a sleep was in flight.
  bool overlapped = false;
  int sleeps_in_flight = 0;
  for (const auto& l : first) {
    if (l.starts_with("> exec") && l.find(" sleep ") != std::string::npos) ++sleeps_in_flight;
    if (l.starts_with("< done")) sleeps_in_flight = std::max(0, sleeps_in_flight - 1);
    if (l.starts_with("< answer") && sleeps_in_flight > 0) overlapped = true;
  }
  EXPECT_TRUE(overlapped);
}

// Regression: an outcome TacticalLevel posts (REPORT's) is still queued when
// the link checks for quiescence; the call its handler makes belongs to the
// same instant, so the advance must wait for it.
TEST(Lockstep, ACallMadeFromAReportsOutcomeGoesInTheSameInstant) {
  Rig rig;
  auto link = rig.connect();
  TacticalLevel t(rig.io, Catalogue::builtin(), link, nullptr, nullptr);
  std::optional<double> asked, asked_after_report;
  t.call("system_problem", {}, [&](CallResult r) {
    ASSERT_TRUE(r.ok()) << r.error().message;
    asked = r.value().sim_time_s;
  });
  t.call("report", {tactical::Value::of("looking")}, [&](CallResult r) {
    ASSERT_TRUE(r.ok());
    t.call("depth_filter_off", {}, [&](CallResult r2) {
      ASSERT_TRUE(r2.ok()) << r2.error().message;
      asked_after_report = r2.value().sim_time_s;
    });
  });
  ASSERT_TRUE(run_until(rig.io, [&] { return asked && asked_after_report; }));
  EXPECT_DOUBLE_EQ(0.1, *asked);
  EXPECT_DOUBLE_EQ(0.1, *asked_after_report);
  EXPECT_EQ(1u, link->advances_sent());
}

// The same for a local error (an unknown primitive), also posted.
TEST(Lockstep, ACallMadeFromALocalErrorGoesInTheSameInstant) {
  Rig rig;
  auto link = rig.connect();
  TacticalLevel t(rig.io, Catalogue::builtin(), link, nullptr, nullptr);
  std::optional<double> asked, asked_after_error;
  t.call("system_problem", {}, [&](CallResult r) { asked = r.value().sim_time_s; });
  t.call("warp_drive", {}, [&](CallResult r) {
    ASSERT_FALSE(r.ok());
    t.call("depth_filter_off", {}, [&](CallResult r2) { asked_after_error = r2.value().sim_time_s; });
  });
  ASSERT_TRUE(run_until(rig.io, [&] { return asked && asked_after_error; }));
  EXPECT_DOUBLE_EQ(0.1, *asked);
  EXPECT_DOUBLE_EQ(0.1, *asked_after_error);
}

TEST(Lockstep, AHoldKeepsTheAdvanceBackUntilItIsLetGo) {
  Rig rig;
  auto link = rig.connect();
  auto hold = link->hold();
  std::optional<double> asked;
  link->send(protocol::make_ask(0, "depth_filter_off"),
             [&](core::Result<VehicleMessage> r) { asked = time_of(r.value()); });
  run_until(
      rig.io, [] { return false; }, 50ms);  // time for a wrong advance to be sent
  EXPECT_FALSE(asked.has_value());
  EXPECT_EQ(0u, link->advances_sent());
  EXPECT_DOUBLE_EQ(0.0, rig.sim.time_s());
  hold.release();
  ASSERT_TRUE(run_until(rig.io, [&] { return asked.has_value(); }));
  EXPECT_DOUBLE_EQ(0.1, *asked);
}

// A vehicle on the other end of a socket, played by a thread: it answers
// each line it reads with the lines `script` gives (each string written on
// its own, after `gap` when it is not the first).
struct ScriptedVehicle {
  using Script = std::function<std::vector<std::string>(const std::string& line)>;
  ScriptedVehicle(Script script, std::chrono::milliseconds gap = 0ms)
      : acceptor(io, {asio::ip::make_address("127.0.0.1"), 0}), port(acceptor.local_endpoint().port()) {
    thread = std::thread([this, script = std::move(script), gap] {
      asio::error_code ec;
      asio::ip::tcp::socket s(io);
      acceptor.accept(s, ec);
      if (ec) return;
      s.set_option(asio::ip::tcp::no_delay(true), ec);
      asio::streambuf in;
      for (;;) {
        asio::read_until(s, in, '\n', ec);
        if (ec) return;
        std::istream is(&in);
        std::string line;
        std::getline(is, line);
        bool first = true;
        for (const auto& out : script(line)) {
          if (!first) std::this_thread::sleep_for(gap);  // separate reads on the other side
          first = false;
          asio::write(s, asio::buffer(out), ec);
          if (ec) return;
        }
      }
    });
  }
  ~ScriptedVehicle() {
    asio::error_code ignored;
    acceptor.close(ignored);
    if (thread.joinable()) thread.join();
  }
  asio::io_context io;
  asio::ip::tcp::acceptor acceptor;
  std::uint16_t port;
  std::thread thread;
};

// Regression guard for determinism: the replies of one instant are handed
// over together when the advance's ok arrives, not one by one as the bytes
// come. Otherwise a call made from the first reply could go before the
// second reply is handled, or even before the next advance, depending on
// how TCP split the lines.
TEST(VehicleLink, RepliesOfOneInstantAreHandedOverTogetherHoweverTheBytesArrive) {
  ScriptedVehicle vehicle(
      [](const std::string& line) -> std::vector<std::string> {
        if (line.starts_with("hello")) return {"ok 1 scripted 2 lockstep\n"};
        if (line.starts_with("advance")) {
          auto id = line.substr(8);
          return {"answer 2 1 0.1\n", "answer 3 0 0.1\n", "ok " + id + "\n"};
        }
        return {};
      },
      30ms);
  asio::io_context io;
  LinkOptions o;
  o.port = vehicle.port;
  o.reconnect_attempts = 0;
  std::vector<std::string> seen;  // arrivals and handler calls, in order
  o.tap = [&](bool sent, std::string_view line) {
    if (!sent) seen.push_back("< " + std::string(line));
  };
  auto link = VehicleLink::create(io, o);
  std::optional<core::Result<protocol::Welcome>> welcome;
  link->connect([&](core::Result<protocol::Welcome> r) { welcome = std::move(r); });
  ASSERT_TRUE(run_until(io, [&] { return welcome.has_value(); }));
  ASSERT_TRUE(welcome->ok()) << welcome->error().message;
  int handled = 0;
  link->send(protocol::make_ask(0, "a"), [&](core::Result<VehicleMessage> r) {
    ASSERT_TRUE(r.ok());
    seen.push_back("handled 2");
    ++handled;
  });
  link->send(protocol::make_ask(0, "b"), [&](core::Result<VehicleMessage> r) {
    ASSERT_TRUE(r.ok());
    seen.push_back("handled 3");
    ++handled;
  });
  ASSERT_TRUE(run_until(io, [&] { return handled == 2; }));
  EXPECT_EQ((std::vector<std::string>{"< ok 1 scripted 2 lockstep", "< answer 2 1 0.1", "< answer 3 0 0.1", "< ok 4",
                                      "handled 2", "handled 3"}),
            seen);
}

// A version-1 vehicle answers hello 2 with its own version: the link keeps
// to version 1 (no advance) rather than refusing it.
TEST(VehicleLink, AVersionOneVehicleIsSpokenToInVersionOne) {
  ScriptedVehicle vehicle([](const std::string& line) -> std::vector<std::string> {
    if (line.starts_with("hello")) return {"ok 1 old 1 lockstep\n"};
    if (line.starts_with("ask 2")) return {"answer 2 1 0.1\n"};
    return {"err 0 unknown_verb \"unexpected\"\n"};
  });
  asio::io_context io;
  LinkOptions o;
  o.port = vehicle.port;
  o.reconnect_attempts = 0;
  auto link = VehicleLink::create(io, o);
  std::optional<core::Result<protocol::Welcome>> welcome;
  link->connect([&](core::Result<protocol::Welcome> r) { welcome = std::move(r); });
  ASSERT_TRUE(run_until(io, [&] { return welcome.has_value(); }));
  ASSERT_TRUE(welcome->ok()) << welcome->error().message;
  EXPECT_EQ(1, link->session_version());
  EXPECT_FALSE(link->lockstep_barrier());
  std::optional<core::Result<VehicleMessage>> reply;
  link->send(protocol::make_ask(0, "p"), [&](core::Result<VehicleMessage> r) { reply = std::move(r); });
  ASSERT_TRUE(run_until(io, [&] { return reply.has_value(); }));
  ASSERT_TRUE(reply->ok()) << reply->error().message;
  EXPECT_EQ(0u, link->advances_sent());
  link->close();
}

TEST(VehicleLink, AVehicleThatDoesNotSpeakTheVersionAskedForIsAClearError) {
  Rig rig;
  LinkOptions o;
  o.port = rig.server->port();
  o.protocol_version = 3;
  o.reconnect_attempts = 0;
  auto link = VehicleLink::create(rig.io, o);
  std::optional<core::Result<protocol::Welcome>> welcome;
  link->connect([&](core::Result<protocol::Welcome> r) { welcome = std::move(r); });
  ASSERT_TRUE(run_until(rig.io, [&] { return welcome.has_value(); }));
  ASSERT_FALSE(welcome->ok());
  EXPECT_NE(std::string::npos, welcome->error().message.find("this vehicle speaks 1 and 2"))
      << welcome->error().message;
}

}  // namespace
}  // namespace strata::tactical
