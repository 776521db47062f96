// The vehicle server spoken to by hand, a line at a time (docs/protocol.md
// §8, §9): protocol 2's advance, the versions it speaks, the hello timeout,
// the watchdog against a client that holds requests without advancing.
// In one process over loopback on a free port.
#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include <asio.hpp>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "tactical/test_rig.h"
#include "tactical/vehicle_link.h"

namespace strata::tactical {
namespace {

using namespace std::chrono_literals;
using testing::LineClient;
using testing::Rig;
using testing::run_until;

// What arrived after the first `skip` lines, sonar ports left out.
std::vector<std::string> after(const LineClient& c, std::size_t skip) {
  std::vector<std::string> out;
  for (std::size_t i = skip; i < c.lines.size(); ++i) out.push_back(c.lines[i]);
  return out;
}

TEST(VehicleServer, InProtocolTwoRequestsWaitForAdvanceAndAreAnsweredInIdOrder) {
  Rig rig;
  LineClient c(rig.io, rig.server->port());
  c.say("hello 1 hand 2");
  ASSERT_TRUE(c.wait_for(rig.io, "ok 1 "));
  EXPECT_TRUE(c.lines[0].starts_with("ok 1 phoenix-sim 2 lockstep")) << c.lines[0];
  c.say("exec 3 sleep 1");
  c.say("ask 2 depth_filter_off");
  c.say("ping 4");
  ASSERT_TRUE(c.wait_for(rig.io, "pong 4"));
  // Nothing is answered before the advance; ping is free.
  EXPECT_EQ((std::vector<std::string>{"pong 4 0.0"}), after(c, 1));
  c.say("advance 5");
  ASSERT_TRUE(c.wait_for(rig.io, "ok 5"));
  EXPECT_EQ((std::vector<std::string>{"pong 4 0.0", "answer 2 1 0.1", "ok 5"}), after(c, 1));
  c.say("advance 6");
  ASSERT_TRUE(c.wait_for(rig.io, "ok 6"));
  // Two requests due at the same cycle come in id order.
  c.say("ask 8 depth_filter_off");
  c.say("ood 7 start_network");
  c.say("advance 9");
  ASSERT_TRUE(c.wait_for(rig.io, "ok 9"));
  // With nothing waiting, an advance does not move time.
  c.say("advance 10");
  c.say("ping 11");
  ASSERT_TRUE(c.wait_for(rig.io, "pong 11"));
  EXPECT_EQ((std::vector<std::string>{"pong 4 0.0", "answer 2 1 0.1", "ok 5", "done 3 1 1.0", "ok 6", "done 7 1 1.1",
                                      "answer 8 1 1.1", "ok 9", "ok 10", "pong 11 1.1"}),
            after(c, 1));
}

// An advance may bound the step (docs/protocol.md §8): time moves no further,
// requests due later wait for a later advance, and the ok says the time.
TEST(VehicleServer, ABoundedAdvanceStopsAtItsTimeAndSaysIt) {
  Rig rig;
  LineClient c(rig.io, rig.server->port());
  c.say("hello 1 hand 2");
  ASSERT_TRUE(c.wait_for(rig.io, "ok 1 "));
  EXPECT_NE(std::string::npos, c.lines[0].find(" time=0.0")) << c.lines[0];
  c.say("exec 2 sleep 5");
  c.say("advance 3 2");
  ASSERT_TRUE(c.wait_for(rig.io, "ok 3"));
  c.say("advance 4 9");
  ASSERT_TRUE(c.wait_for(rig.io, "ok 4"));
  // Nothing waiting: a bounded advance still moves time, to its bound.
  c.say("advance 5 7.5");
  ASSERT_TRUE(c.wait_for(rig.io, "ok 5"));
  // A bound in the past moves nothing.
  c.say("advance 6 1");
  ASSERT_TRUE(c.wait_for(rig.io, "ok 6"));
  EXPECT_EQ((std::vector<std::string>{"ok 3 2.0", "done 2 1 5.0", "ok 4 5.0", "ok 5 7.5", "ok 6 7.5"}), after(c, 1));
}

// A hostile bound cannot hold the event loop: an advance moves at most an
// hour of simulated time.
TEST(VehicleServer, ABoundedAdvanceMovesAtMostAnHour) {
  Rig rig;
  LineClient c(rig.io, rig.server->port());
  c.say("hello 1 hand 2");
  ASSERT_TRUE(c.wait_for(rig.io, "ok 1 "));
  c.say("advance 2 1e12");
  ASSERT_TRUE(c.wait_for(rig.io, "ok 2"));
  EXPECT_EQ((std::vector<std::string>{"ok 2 3600.0"}), after(c, 1));
}

// In lockstep the clock is the simulator's: a lost link drops every line but
// a bounded advance, which still moves time; the watchdog trips watchdog_s
// simulated seconds into the silence.
TEST(VehicleServer, ALostLinkStillCarriesTheLockstepClock) {
  vehicle::Scenario lost = vehicle::Scenario::nominal();
  lost.faults.push_back({vehicle::FaultKind::LinkLoss, 1.0, 1.0, std::nullopt});
  Rig rig(lost);
  LineClient c(rig.io, rig.server->port());
  c.say("hello 1 hand 2");
  ASSERT_TRUE(c.wait_for(rig.io, "ok 1 "));
  c.say("ood 2 start_network");
  c.say("advance 3 1.5");
  ASSERT_TRUE(c.wait_for(rig.io, "ok 3"));
  c.say("advance 4 1.5");  // nothing waiting: the bound reached
  ASSERT_TRUE(c.wait_for(rig.io, "ok 4"));
  c.say("ping 5");               // lost
  c.say("ask 6 depth_reached");  // lost
  c.say("advance 7");            // unbounded: lost as well
  c.say("advance 8 6");
  ASSERT_TRUE(c.wait_for(rig.io, "ok 8"));
  EXPECT_EQ((std::vector<std::string>{"done 2 1 0.1", "ok 3 0.1", "ok 4 1.5", "ok 8 6.0"}), after(c, 1));
  EXPECT_TRUE(rig.sim.watchdog_tripped());
  bool tripped_in_time = false;
  for (const auto& line : rig.vehicle_log)
    tripped_in_time |= line == "4.0 s: watchdog: link silent for 3.0 s: surfacing";
  EXPECT_TRUE(tripped_in_time) << ::testing::PrintToString(rig.vehicle_log);
}

TEST(VehicleServer, AdvanceIsProtocolTwo) {
  Rig rig;
  LineClient c(rig.io, rig.server->port());
  c.say("hello 1 hand 1");
  ASSERT_TRUE(c.wait_for(rig.io, "ok 1 "));
  EXPECT_TRUE(c.lines[0].starts_with("ok 1 phoenix-sim 1 lockstep")) << c.lines[0];
  c.say("advance 2");
  ASSERT_TRUE(c.wait_for(rig.io, "err 2"));
  EXPECT_TRUE(c.lines[1].starts_with("err 2 unknown_verb \"'advance' is protocol 2")) << c.lines[1];
  // Version 1: the request moves time itself.
  c.say("exec 3 sleep 1");
  ASSERT_TRUE(c.wait_for(rig.io, "done 3"));
  EXPECT_EQ("done 3 1 1.0", c.lines[2]);
}

TEST(VehicleServer, OnTheWallClockAdvanceIsAnsweredAtOnce) {
  Rig rig(vehicle::Scenario::nominal(), protocol::ClockMode::Wall);
  LineClient c(rig.io, rig.server->port());
  c.say("hello 1 hand 2");
  ASSERT_TRUE(c.wait_for(rig.io, "ok 1 "));
  EXPECT_NE(std::string::npos, c.lines[0].find(" 2 wall")) << c.lines[0];
  c.say("advance 2");
  EXPECT_TRUE(c.wait_for(rig.io, "ok 2"));
}

// Regression (issue 39): on the wall clock, a run that lost its link let the
// embedded vehicle go at once (`strata run --speed 10` left it at 1.26 m).
// when_settled waits until the vehicle, its watchdog tripped, is at the
// surface by itself.
TEST(VehicleServer, OnTheWallClockAVehicleLeftAtDepthIsSettledOnlyAtTheSurface) {
  Rig rig(vehicle::Scenario::nominal(), protocol::ClockMode::Wall);  // speed 20
  auto link = rig.connect();
  EXPECT_TRUE(rig.call(*link, protocol::make_ood(0, "start_network")).ok());
  EXPECT_TRUE(rig.exec(*link, "setpoint", {protocol::Value::real(1.5), protocol::Value::integer(60)}));
  EXPECT_TRUE(rig.exec(*link, "start_depth_filter"));
  EXPECT_TRUE(rig.exec(*link, "submerge"));
  EXPECT_TRUE(rig.exec(*link, "sleep", {protocol::Value::integer(8)}));
  ASSERT_GT(rig.sim.heave().depth_m, 0.5);
  link->close();
  rig.server->controller_gone();
  bool settled = false;
  std::optional<double> depth_when_settled;
  rig.server->when_settled([&] {
    settled = true;
    depth_when_settled = rig.sim.heave().depth_m;
  });
  ASSERT_TRUE(run_until(
      rig.io, [&] { return settled; }, 60s));
  ASSERT_TRUE(depth_when_settled.has_value());
  EXPECT_LE(*depth_when_settled, rig.sim.params().surface_depth_m + 0.05);
  EXPECT_TRUE(rig.sim.watchdog_tripped());
}

// Regression (found by LockstepMission.LockstepAndTheWallClockAgree): on the
// wall clock the sleeps waited in arrival order, so a `sleep 2` sent after a
// `sleep 5` was answered with it, at 5 s.
TEST(VehicleServer, OnTheWallClockAShortSleepIsNotHeldBehindALongerOne) {
  Rig rig(vehicle::Scenario::nominal(), protocol::ClockMode::Wall);  // speed 20
  LineClient c(rig.io, rig.server->port());
  c.say("hello 1 hand 2");
  ASSERT_TRUE(c.wait_for(rig.io, "ok 1 "));
  c.say("exec 2 sleep 1");
  c.say("exec 3 sleep 0.5");
  ASSERT_TRUE(c.wait_for(rig.io, "done 2"));
  const auto done = c.starting("done");
  ASSERT_EQ(2u, done.size());
  ASSERT_TRUE(done[0].starts_with("done 3 1 ")) << done[0];
  const double short_s = std::stod(done[0].substr(9));
  const double long_s = std::stod(done[1].substr(9));
  EXPECT_NEAR(0.5, long_s - short_s, 0.1 + 1e-9) << done[0] << " / " << done[1];
}

TEST(VehicleServer, HelloWithAnUnsupportedVersionIsRefusedNamingTheVersionsSpoken) {
  Rig rig;
  LineClient c(rig.io, rig.server->port());
  c.say("hello 1 hand 99");
  ASSERT_TRUE(c.wait_for(rig.io, "err 1"));
  EXPECT_EQ("err 1 bad_argument \"protocol version 99 is not spoken here; this vehicle speaks 1 and 2\"", c.lines[0]);
  // No session: other requests wait for a hello it accepts.
  c.say("ping 2");
  ASSERT_TRUE(c.wait_for(rig.io, "err 2"));
  EXPECT_TRUE(c.lines[1].starts_with("err 2 not_ready")) << c.lines[1];
  c.say("hello 3 hand 2");
  ASSERT_TRUE(c.wait_for(rig.io, "ok 3"));
  EXPECT_TRUE(c.lines[2].starts_with("ok 3 phoenix-sim 2 lockstep")) << c.lines[2];
}

// Regression (issue 15): a client that connected and never said hello held
// the vehicle for ever. It is closed after its hello timeout, saying why.
TEST(VehicleServer, AClientThatNeverSaysHelloIsClosedAfterItsTimeout) {
  Rig rig(vehicle::Scenario::nominal(), protocol::ClockMode::Lockstep, vehicle::default_params(),
          [](vehicle::ServerOptions& so) { so.hello_timeout_s = 0.3; });
  LineClient silent(rig.io, rig.server->port());
  ASSERT_TRUE(run_until(rig.io, [&] {
    silent.poll();
    return silent.closed;
  }));
  ASSERT_EQ(1u, silent.lines.size());
  EXPECT_EQ("err 0 not_ready \"no hello within 0.3 s: closing this connection\"", silent.lines[0]);
  auto served = rig.connect();
  EXPECT_TRUE(served->connected());
  EXPECT_TRUE(rig.ask(*served, "depth_filter_off"));
  EXPECT_EQ(0u, rig.server->clients_refused());
}

// Regression (issue 39): while a client that said nothing was within its
// hello timeout, a real controller was refused `busy`. The first accepted
// hello takes the vehicle; the silent client is refused then, and heard
// nothing before (no heartbeat, no telemetry).
TEST(VehicleServer, ASilentClientNeverBlocksARealController) {
  Rig rig(vehicle::Scenario::nominal(), protocol::ClockMode::Lockstep, vehicle::default_params(),
          [](vehicle::ServerOptions& so) { so.hello_timeout_s = 3600; });
  LineClient silent(rig.io, rig.server->port());
  LineClient early(rig.io, rig.server->port());
  early.say("ping 1");  // not a hello: not served, and holds nothing
  ASSERT_TRUE(early.wait_for(rig.io, "err 1"));
  EXPECT_EQ("err 1 not_ready \"say hello first\"", early.lines[0]);

  auto served = rig.connect();
  ASSERT_TRUE(served->connected());
  EXPECT_TRUE(rig.ask(*served, "depth_filter_off"));
  ASSERT_TRUE(run_until(rig.io, [&] {
    silent.poll();
    early.poll();
    return silent.closed && early.closed;
  }));
  ASSERT_EQ(1u, silent.lines.size()) << "a client without a hello hears nothing but its refusal";
  EXPECT_EQ("err 0 busy \"another client controls the vehicle\"", silent.lines[0]);
  EXPECT_EQ("err 0 busy \"another client controls the vehicle\"", early.lines.back());

  // While it controls the vehicle, a newcomer is refused at once.
  LineClient late(rig.io, rig.server->port());
  late.say("hello 5 late 2");
  ASSERT_TRUE(run_until(rig.io, [&] {
    late.poll();
    return late.closed;
  }));
  ASSERT_FALSE(late.lines.empty());
  EXPECT_EQ("err 0 busy \"another client controls the vehicle\"", late.lines[0]);
  EXPECT_TRUE(rig.ask(*served, "depth_filter_off"));
  EXPECT_EQ(3u, rig.server->clients_refused());
}

// At most kMaxWaitingClients wait for their hello at once.
TEST(VehicleServer, TooManyClientsWithoutAHelloAreRefused) {
  Rig rig(vehicle::Scenario::nominal(), protocol::ClockMode::Lockstep, vehicle::default_params(),
          [](vehicle::ServerOptions& so) { so.hello_timeout_s = 3600; });
  std::vector<std::unique_ptr<LineClient>> waiting;
  for (std::size_t i = 0; i < vehicle::kMaxWaitingClients; ++i) {
    waiting.push_back(std::make_unique<LineClient>(rig.io, rig.server->port()));
    waiting.back()->say("ping 1");
    ASSERT_TRUE(waiting.back()->wait_for(rig.io, "err 1"));  // accepted, waiting
  }
  LineClient one_more(rig.io, rig.server->port());
  ASSERT_TRUE(run_until(rig.io, [&] {
    one_more.poll();
    return one_more.closed;
  }));
  ASSERT_EQ(1u, one_more.lines.size());
  EXPECT_EQ(0u, one_more.lines[0].find("err 0 busy")) << one_more.lines[0];
  waiting.back()->say("hello 2 hand 2");  // one of them still gets the vehicle
  ASSERT_TRUE(waiting.back()->wait_for(rig.io, "ok 2"));
}

// A controller that said hello is not subject to the hello timeout.
TEST(VehicleServer, TheHelloTimeoutEndsWithTheHello) {
  Rig rig(vehicle::Scenario::nominal(), protocol::ClockMode::Lockstep, vehicle::default_params(),
          [](vehicle::ServerOptions& so) { so.hello_timeout_s = 0.1; });
  LineClient c(rig.io, rig.server->port());
  c.say("hello 1 hand 2");
  ASSERT_TRUE(c.wait_for(rig.io, "ok 1"));
  run_until(
      rig.io, [] { return false; }, 300ms);  // past the hello timeout
  c.say("ping 2");
  ASSERT_TRUE(c.wait_for(rig.io, "pong 2"));
  EXPECT_FALSE(c.closed);
}

// A protocol-2 session whose network is up (requests 1 to 3 used).
bool start_network(Rig& rig, LineClient& c) {
  c.say("hello 1 hand 2");
  c.say("ood 2 start_network");
  c.say("advance 3");
  return c.wait_for(rig.io, "ok 3");
}

// The watchdog in protocol 2: silence counts from the last line received or
// reply sent, so a client holding requests without advancing is silent, and
// when the watchdog trips it is told what became of them.
TEST(VehicleServer, RequestsHeldWithoutAnAdvanceAreSilenceAndTheWatchdogTrips) {
  vehicle::VehicleParams params = vehicle::default_params();
  params.watchdog_s = 0.2;  // wall seconds of silence, in lockstep
  Rig rig(vehicle::Scenario::nominal(), protocol::ClockMode::Lockstep, params);
  LineClient c(rig.io, rig.server->port());
  ASSERT_TRUE(start_network(rig, c));
  c.say("exec 4 sleep 1");
  ASSERT_TRUE(c.wait_for(rig.io, "err 4", 3000ms));
  EXPECT_TRUE(c.starting("err 4")[0].starts_with("err 4 not_ready \"the watchdog tripped")) << c.starting("err 4")[0];
  EXPECT_TRUE(rig.sim.watchdog_tripped());
  bool said_why = false;
  for (const auto& line : rig.vehicle_log) said_why |= line.find("link silent for 0.2 s") != std::string::npos;
  EXPECT_TRUE(said_why) << ::testing::PrintToString(rig.vehicle_log);
}

// The silence watchdog keeps one wait and, when it ends early, waits again
// for the newest deadline (it is not re-armed at each line): a client that
// speaks more often than the watchdog's limit, for longer than it, is never
// silent. 3 s of limit, a line each 0.2 s for 7 s.
TEST(VehicleServer, InLockstepLinesMoreOftenThanTheLimitKeepTheWatchdogQuietPastIt) {
  vehicle::VehicleParams params = vehicle::default_params();
  params.watchdog_s = 3.0;
  Rig rig(vehicle::Scenario::nominal(), protocol::ClockMode::Lockstep, params);
  LineClient c(rig.io, rig.server->port());
  ASSERT_TRUE(start_network(rig, c));
  for (int i = 0; i < 35; ++i) {
    run_until(
        rig.io, [] { return false; }, 200ms);
    c.say(fmt::format("ping {}", 10 + i));
    ASSERT_TRUE(c.wait_for(rig.io, fmt::format("pong {}", 10 + i)));
  }
  EXPECT_FALSE(rig.sim.watchdog_tripped()) << ::testing::PrintToString(rig.vehicle_log);
  // ...and silence after the last line still trips it.
  ASSERT_TRUE(run_until(
      rig.io, [&] { return rig.sim.watchdog_tripped(); }, 30000ms));
}

// ...while a client that keeps advancing is not silent, however much
// simulated time its calls cover: the watchdog counts wall time in lockstep.
// 5 s of limit against 20 s of simulated time: a limit of 0.2 s tripped
// once on a loaded machine (an asan test beside two builds), between two
// of the asks.
TEST(VehicleServer, InLockstepAClientThatKeepsAdvancingIsNotSilent) {
  vehicle::VehicleParams params = vehicle::default_params();
  params.watchdog_s = 5.0;
  Rig rig(vehicle::Scenario::nominal(), protocol::ClockMode::Lockstep, params);
  auto link = rig.connect();
  ASSERT_TRUE(rig.call(*link, protocol::make_ood(0, "start_network")).ok());
  int asks = 0;
  bool slept = false;
  link->send(protocol::make_exec(0, "sleep", {protocol::Value::integer(20)}),
             [&](const core::Result<protocol::VehicleMessage>& r) { slept = r.ok(); });
  std::function<void()> ask = [&] {
    link->send(protocol::make_ask(0, "system_problem"), [&](const core::Result<protocol::VehicleMessage>& r) {
      if (r.ok() && ++asks < 150) ask();
    });
  };
  ask();
  ASSERT_TRUE(run_until(rig.io, [&] { return slept && asks == 150; }));
  EXPECT_FALSE(rig.sim.watchdog_tripped()) << ::testing::PrintToString(rig.vehicle_log);
  EXPECT_NEAR(20.1, rig.sim.time_s(), 1e-9);
}

TEST(VehicleServer, ARequestIdAlreadyInFlightIsRefused) {
  Rig rig;
  LineClient c(rig.io, rig.server->port());
  c.say("hello 1 hand 2");
  c.say("exec 2 sleep 1");
  c.say("exec 2 sleep 2");
  ASSERT_TRUE(c.wait_for(rig.io, "err 2"));
  EXPECT_TRUE(c.starting("err 2")[0].starts_with("err 2 duplicate_id")) << c.starting("err 2")[0];
  c.say("advance 3");
  ASSERT_TRUE(c.wait_for(rig.io, "ok 3"));
  EXPECT_EQ((std::vector<std::string>{"done 2 1 1.0"}), c.starting("done"));
}

// Regression (issue 15): the sonar's event named its port, which is random,
// so two runs of the same mission logged different bytes.
TEST(VehicleServer, TheSonarEventCarriesNoPort) {
  Rig rig;
  auto link = rig.connect();
  std::vector<std::string> events;
  link->on_event([&](const protocol::Event& e) { events.push_back(e.text); });
  ASSERT_TRUE(rig.call(*link, protocol::make_ood(0, "start_network")).ok());
  ASSERT_TRUE(rig.exec(*link, "start_sonar"));
  ASSERT_TRUE(rig.exec(*link, "sleep", {protocol::Value::integer(1)}));
  ASSERT_TRUE(rig.exec(*link, "stop_sonar"));
  ASSERT_TRUE(rig.exec(*link, "sleep", {protocol::Value::integer(1)}));
  EXPECT_EQ((std::vector<std::string>{"sonar on", "sonar off"}), events);
  // The vehicle's own log (its operator's console) still says where the pings go.
  bool told = false;
  for (const auto& line : rig.vehicle_log) {
    told |= line.find("sonar on: pings on port " + std::to_string(rig.server->sonar_port())) != std::string::npos;
  }
  EXPECT_TRUE(told) << ::testing::PrintToString(rig.vehicle_log);
}

}  // namespace
}  // namespace strata::tactical
