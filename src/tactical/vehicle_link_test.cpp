// The Tactical level's link against the real Execution-level server, in one
// process on one io_context, over loopback TCP on a free port.
#include <chrono>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <asio.hpp>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "protocol/codec.h"
#include "tactical/test_rig.h"
#include "tactical/vehicle_link.h"
#include "vehicle/server.h"

namespace strata::tactical {
namespace {

using namespace std::chrono_literals;
using protocol::VehicleMessage;
using testing::Rig;
using testing::run_until;
using testing::ScriptedPeer;

TEST(VehicleLink, HelloIsAnsweredWithTheVehicleAndItsClock) {
  Rig rig;
  auto link = rig.connect();
  EXPECT_TRUE(link->connected());
}

TEST(VehicleLink, EveryRequestCostsOneCycleInLockstep) {
  Rig rig;
  auto link = rig.connect();
  auto ood = rig.call(*link, protocol::make_ood(0, "start_network"));
  ASSERT_TRUE(ood.ok());
  EXPECT_TRUE(std::get<protocol::Done>(ood.value()).success);
  EXPECT_NEAR(0.1, rig.sim.time_s(), 1e-9);
  EXPECT_TRUE(rig.ask(*link, "depth_filter_off"));
  EXPECT_NEAR(0.2, rig.sim.time_s(), 1e-9);
  EXPECT_TRUE(rig.exec(*link, "sleep", {protocol::Value::integer(2)}));
  EXPECT_NEAR(2.2, rig.sim.time_s(), 1e-9);
  auto pong = rig.call(*link, protocol::make_ping(0));
  ASSERT_TRUE(pong.ok());
  EXPECT_NEAR(2.2, std::get<protocol::Pong>(pong.value()).sim_time_s, 1e-9);  // ping is free
}

// Sends ood, sleep 1, ask and ping at once; returns (id, what) in reply order.
std::vector<std::pair<protocol::RequestId, std::string>> four_at_once(Rig& rig, VehicleLink& link,
                                                                      std::vector<protocol::RequestId>& ids) {
  std::vector<std::pair<protocol::RequestId, std::string>> replies;
  auto record = [&](std::string what) {
    return [&replies, what](core::Result<VehicleMessage> m) {
      ASSERT_TRUE(m.ok()) << m.error().message;
      replies.emplace_back(*protocol::reply_id(m.value()), what);
    };
  };
  ids.push_back(link.send(protocol::make_ood(0, "start_network"), record("ood")));
  ids.push_back(link.send(protocol::make_exec(0, "sleep", {protocol::Value::integer(1)}), record("sleep")));
  ids.push_back(link.send(protocol::make_ask(0, "depth_filter_off"), record("ask")));
  ids.push_back(link.send(protocol::make_ping(0), record("ping")));
  EXPECT_EQ(4u, link.in_flight());
  EXPECT_TRUE(run_until(rig.io, [&] { return replies.size() == 4; }));
  EXPECT_EQ(0u, link.in_flight());
  return replies;
}

TEST(VehicleLink, SeveralRequestsInFlightShareSimulatedTimeInLockstep) {
  Rig rig;
  auto link = rig.connect();
  EXPECT_TRUE(link->lockstep_barrier());
  std::vector<protocol::RequestId> ids;
  auto replies = four_at_once(rig, *link, ids);
  // ping is free and answered at once; ood and ask cost the same first
  // cycle (answered in id order); the sleep ends 1 s after it was sent.
  EXPECT_EQ((std::vector<std::pair<protocol::RequestId, std::string>>{
                {ids[3], "ping"}, {ids[0], "ood"}, {ids[2], "ask"}, {ids[1], "sleep"}}),
            replies);
  EXPECT_NEAR(1.0, rig.sim.time_s(), 1e-9);
}

// Protocol 1, as a client that never sends advance: each request moves time
// itself, in arrival order.
TEST(VehicleLink, ProtocolOneServesRequestsOneAfterTheOther) {
  Rig rig;
  LinkOptions o;
  o.protocol_version = 1;
  auto link = rig.connect(o);
  EXPECT_EQ(1, link->session_version());
  EXPECT_FALSE(link->lockstep_barrier());
  std::vector<protocol::RequestId> ids;
  auto replies = four_at_once(rig, *link, ids);
  EXPECT_EQ((std::vector<std::pair<protocol::RequestId, std::string>>{
                {ids[0], "ood"}, {ids[1], "sleep"}, {ids[2], "ask"}, {ids[3], "ping"}}),
            replies);
  EXPECT_NEAR(1.2, rig.sim.time_s(), 1e-9);  // 0.1 + 1.0 + 0.1; ping is free
  EXPECT_EQ(0u, link->advances_sent());
}

TEST(VehicleLink, UnknownFunctionAndBadArgumentsAreRefusedWithReasons) {
  Rig rig;
  auto link = rig.connect();
  // The vehicle's `err` is its answer: handed over as a value, code and all.
  auto refusal = [&](protocol::Request request) -> protocol::Err {
    auto r = rig.call(*link, std::move(request));
    EXPECT_TRUE(r.ok()) << r.error().message;
    const auto* err = r.ok() ? std::get_if<protocol::Err>(&r.value()) : nullptr;
    EXPECT_NE(nullptr, err);
    return err ? *err : protocol::Err{};
  };
  EXPECT_EQ(protocol::ErrorCode::UnknownFunction, refusal(protocol::make_exec(0, "fly")).code);
  EXPECT_EQ(protocol::ErrorCode::BadArgument, refusal(protocol::make_exec(0, "sleep")).code);
  const protocol::Err ask = refusal(protocol::make_exec(0, "depth_reached"));
  EXPECT_EQ(protocol::ErrorCode::UnknownFunction, ask.code);
  EXPECT_NE(std::string::npos, ask.message.find("is an ask function")) << ask.message;
}

TEST(VehicleLink, AFailedFunctionIsDoneZeroWithAnEventSayingWhy) {
  Rig rig;
  auto link = rig.connect();
  std::vector<std::string> events;
  link->on_event([&](const protocol::Event& e) { events.push_back(e.text); });
  EXPECT_FALSE(rig.exec(*link, "submerge"));  // network not started
  ASSERT_FALSE(events.empty());
  EXPECT_NE(std::string::npos, events[0].find("submerge failed")) << events[0];
}

// The Figure 10 call sequence (phase 2), issued from the Tactical side.
bool figure10_phase2(Rig& rig, VehicleLink& link, double depth_m, double timeout_s) {
  EXPECT_TRUE(rig.call(link, protocol::make_ood(0, "start_network")).ok());
  EXPECT_TRUE(rig.exec(link, "setpoint", {protocol::Value::real(depth_m), protocol::Value::real(timeout_s)}));
  if (rig.ask(link, "depth_filter_off")) {
    EXPECT_TRUE(rig.exec(link, "start_depth_filter"));
    EXPECT_TRUE(rig.exec(link, "sleep", {protocol::Value::integer(1)}));
  }
  EXPECT_TRUE(rig.exec(link, "submerge"));
  EXPECT_TRUE(rig.exec(link, "start_timer"));
  for (int i = 0; i < 1000; ++i) {
    EXPECT_TRUE(rig.exec(link, "sleep", {protocol::Value::integer(1)}));
    if (rig.ask(link, "depth_reached")) return true;
    if (rig.ask(link, "time_out") || rig.ask(link, "system_problem")) {
      EXPECT_TRUE(rig.exec(link, "surface"));
      for (int j = 0; j < 1000 && !rig.ask(link, "surface_reached"); ++j) {}
      return false;
    }
  }
  ADD_FAILURE() << "phase 2 neither completed nor aborted";
  return false;
}

TEST(Figure10, Phase2ReachesDepthInNominal) {
  Rig rig;
  auto link = rig.connect();
  EXPECT_TRUE(figure10_phase2(rig, *link, 0.6, 30));
  EXPECT_NEAR(0.6, rig.sim.heave().depth_m, 0.15);
}

TEST(Figure10, Phase2TimesOutWithWeakThrusters) {
  vehicle::Scenario weak = vehicle::Scenario::nominal();
  weak.faults.push_back({vehicle::FaultKind::WeakThrusters, 0.0, 0.1, std::nullopt});
  Rig rig(weak);
  auto link = rig.connect();
  EXPECT_FALSE(figure10_phase2(rig, *link, 0.6, 30));
  EXPECT_TRUE(rig.sim.time_out());
  EXPECT_TRUE(rig.sim.surface_reached());
}

TEST(VehicleLink, TelemetryFlowsAtTheRequestedRateOfSimTime) {
  Rig rig;
  auto link = rig.connect();
  std::vector<protocol::Telemetry> samples;
  link->on_telemetry([&](const protocol::Telemetry& t) { samples.push_back(t); });
  ASSERT_TRUE(rig.call(*link, protocol::make_telemetry(0, 2.0)).ok());
  EXPECT_TRUE(rig.exec(*link, "sleep", {protocol::Value::integer(3)}));
  ASSERT_TRUE(run_until(rig.io, [&] { return samples.size() >= 6; }));
  EXPECT_EQ(6u, samples.size());
  EXPECT_NEAR(0.5, samples[1].sim_time_s - samples[0].sim_time_s, 1e-6);
  EXPECT_TRUE(samples[0].depth_m.has_value());
}

TEST(VehicleLink, ASecondClientIsRefused) {
  Rig rig;
  auto first = rig.connect();
  LinkOptions o;
  o.port = rig.server->port();
  o.reconnect_attempts = 0;
  auto second = VehicleLink::create(rig.io, o);
  std::optional<core::Result<protocol::Welcome>> welcome;
  second->connect([&](core::Result<protocol::Welcome> r) { welcome = std::move(r); });
  ASSERT_TRUE(run_until(rig.io, [&] { return welcome.has_value(); }));
  ASSERT_FALSE(welcome->ok());
  EXPECT_NE(std::string::npos, welcome->error().message.find("busy")) << welcome->error().message;
  EXPECT_EQ(1u, rig.server->clients_refused());
  EXPECT_TRUE(rig.ask(*first, "depth_filter_off"));  // the first still works
}

// Regression: a refused hello left the socket open, so the link reconnected
// on its own after reporting the refusal.
TEST(VehicleLink, ARefusedHelloDoesNotReconnect) {
  Rig rig;
  auto first = rig.connect();
  LinkOptions o;
  o.port = rig.server->port();
  o.reconnect_attempts = 3;
  o.reconnect_delay = 10ms;
  auto second = VehicleLink::create(rig.io, o);
  std::optional<core::Result<protocol::Welcome>> welcome;
  second->connect([&](core::Result<protocol::Welcome> r) { welcome = std::move(r); });
  ASSERT_TRUE(run_until(rig.io, [&] { return welcome.has_value(); }));
  ASSERT_FALSE(welcome->ok());
  run_until(
      rig.io, [] { return false; }, 200ms);  // time for any reconnect to happen
  EXPECT_FALSE(second->connected());
  EXPECT_EQ(1u, rig.server->clients_refused());
}

// Regression: in wall mode a sleep owed to a client that left was answered
// to the next client, whose request ids start again at 1.
TEST(VehicleServer, RepliesOwedToAClientThatLeftAreNotSentToTheNext) {
  Rig rig(vehicle::Scenario::nominal(), protocol::ClockMode::Wall);  // speed 20
  {
    auto a = rig.connect();
    a->send(protocol::make_exec(0, "sleep", {protocol::Value::integer(2)}), [](auto) {});
    run_until(
        rig.io, [] { return false; }, 20ms);
    a->close();
  }
  run_until(
      rig.io, [] { return false; }, 20ms);
  auto b = rig.connect();
  double start = rig.sim.time_s();
  // Same id as a's sleep (both links number from 1); a's would come first.
  auto r = rig.call(*b, protocol::make_exec(0, "sleep", {protocol::Value::integer(5)}));
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_GE(std::get<protocol::Done>(r.value()).sim_time_s, start + 5.0 - 1e-9);
}

TEST(VehicleLink, ASilentVehicleIsATimeoutNotAHang) {
  // link_loss from the start: the vehicle drops every line after hello.
  vehicle::Scenario lost = vehicle::Scenario::nominal();
  lost.faults.push_back({vehicle::FaultKind::LinkLoss, 0.05, 1.0, std::nullopt});
  Rig rig(lost);
  auto link = rig.connect();
  // This request's cycle crosses into the loss: its reply is lost too.
  auto r = rig.call(*link, protocol::make_ood(0, "start_network"), 200ms);
  EXPECT_FALSE(r.ok());
  auto r2 = rig.call(*link, protocol::make_ask(0, "depth_reached"), 200ms);
  ASSERT_FALSE(r2.ok());
  EXPECT_EQ(core::ErrorCode::Timeout, r2.error().code);
  EXPECT_NE(std::string::npos, r2.error().message.find("no reply to `ask depth_reached`")) << r2.error().message;
}

// Lockstep: a request sent with a simulated timeout fails that many
// simulated seconds later when the vehicle is silent (the lost link still
// carries the clock), whatever the wall clock says.
TEST(VehicleLink, InLockstepASilentVehicleTimesOutInSimulatedTime) {
  vehicle::Scenario lost = vehicle::Scenario::nominal();
  lost.faults.push_back({vehicle::FaultKind::LinkLoss, 0.5, 1.0, std::nullopt});
  Rig rig(lost);
  auto link = rig.connect();
  ASSERT_TRUE(rig.call(*link, protocol::make_ood(0, "start_network")).ok());
  ASSERT_EQ(std::optional<double>(0.1), link->sim_time_s());
  std::optional<core::Result<VehicleMessage>> reply;
  link->send(
      protocol::make_exec(0, "sleep", {protocol::Value::integer(1)}),
      [&](core::Result<VehicleMessage> m) { reply = std::move(m); }, 60000ms, 3.0);
  ASSERT_TRUE(run_until(rig.io, [&] { return reply.has_value(); }));
  ASSERT_FALSE(reply->ok());
  EXPECT_EQ(core::ErrorCode::Timeout, reply->error().code);
  EXPECT_EQ("no reply to `exec sleep 1` (request 4) within 3 s of simulated time", reply->error().message);
  EXPECT_EQ(std::optional<double>(3.1), link->sim_time_s());
  EXPECT_NEAR(3.1, rig.sim.time_s(), 1e-9);
}

// A lockstep vehicle whose welcome does not tell its time may not take a
// bounded advance: the link sends plain ones (else such a vehicle would
// refuse every advance and the link would send the next at once, for ever).
TEST(VehicleLink, AVehicleThatDoesNotTellItsTimeGetsPlainAdvances) {
  ScriptedPeer peer([](ScriptedPeer& p) {
    p.hear();  // hello 1 strata 2
    p.say("ok 1 older-sim 2 lockstep\n");
    p.hear();  // ask 2 depth_reached (a reply, then the advance)
    p.hear();  // advance 3
    p.say("answer 2 1 0.1\nok 3\n");
    p.hear();  // ask 4 depth_reached: sim time known from the answer now
    p.hear();  // advance 5: still plain
    p.say("answer 4 0 0.2\nok 5\n");
  });
  asio::io_context io;
  LinkOptions o;
  o.port = peer.port();
  auto link = testing::connect_link(io, o);
  ASSERT_FALSE(::testing::Test::HasFailure()) << "no welcome";
  for (int i = 0; i < 2; ++i) {
    std::optional<core::Result<VehicleMessage>> reply;
    link->send(
        protocol::make_ask(0, "depth_reached"), [&](core::Result<VehicleMessage> m) { reply = std::move(m); }, 5000ms,
        2.0);
    if (!run_until(io, [&] { return reply.has_value(); }) || !reply->ok()) {
      ADD_FAILURE() << (reply ? reply->error().message : "no reply");
      break;
    }
  }
  link->close();  // a peer still waiting for a line reads the end
  EXPECT_EQ((std::vector<std::string>{"hello 1 strata 2", "ask 2 depth_reached", "advance 3", "ask 4 depth_reached",
                                      "advance 5"}),
            peer.join());
}

// Regression (review): a reply's handler that sends a new request at the
// end of an instant counted its simulated timeout from the time before the
// instant, so the request timed out at once, before the vehicle saw it.
TEST(VehicleLink, ARequestSentAtTheEndOfAnInstantCountsItsTimeoutFromThatInstant) {
  ScriptedPeer peer([](ScriptedPeer& p) {
    p.hear();  // hello 1 strata 2
    p.say("ok 1 sim 2 lockstep time=0\n");
    p.hear();  // exec 2 sleep 60
    p.hear();  // ask 3 leak
    p.hear();  // advance 4 2.0: the ask's deadline
    // The ask is refused (an err carries no time); the instant ends at 2.0.
    p.say("err 3 failed \"no leak sensor\"\nok 4 2.0\n");
    p.hear();  // ask 5 depth_reached, sent by the ask's handler at 2.0
    p.hear();  // advance 6 4.0: two seconds from 2.0
    p.say("answer 5 1 2.1\nok 6 2.1\n");
  });
  asio::io_context io;
  LinkOptions o;
  o.port = peer.port();
  auto link = testing::connect_link(io, o);
  ASSERT_FALSE(::testing::Test::HasFailure()) << "no welcome";
  std::optional<core::Result<VehicleMessage>> second;
  link->send(
      protocol::make_exec(0, "sleep", {protocol::Value::integer(60)}), [](const core::Result<VehicleMessage>&) {},
      5000ms, 62.0);
  link->send(
      protocol::make_ask(0, "leak"),
      [&](const core::Result<VehicleMessage>&) {
        link->send(
            protocol::make_ask(0, "depth_reached"), [&](core::Result<VehicleMessage> m) { second = std::move(m); },
            5000ms, 2.0);
      },
      5000ms, 2.0);
  const bool replied = run_until(io, [&] { return second.has_value(); });
  link->close();  // a peer still waiting for a line reads the end
  const std::vector<std::string>& heard = peer.join();
  ASSERT_TRUE(replied);
  EXPECT_TRUE(second->ok()) << second->error().message;
  EXPECT_EQ((std::vector<std::string>{"hello 1 strata 2", "exec 2 sleep 60", "ask 3 leak", "advance 4 2.0",
                                      "ask 5 depth_reached", "advance 6 4.0"}),
            heard);
}

TEST(VehicleLink, VehicleGoneMidRequestFailsThePendingRequest) {
  Rig rig;
  LinkOptions o;
  o.reconnect_attempts = 1;
  o.reconnect_delay = 20ms;
  auto link = rig.connect(o);
  std::optional<core::Error> lost;
  link->on_lost([&](const core::Error& e) { lost = e; });
  std::optional<core::Result<VehicleMessage>> reply;
  link->send(protocol::make_exec(0, "sleep", {protocol::Value::integer(1)}),
             [&](core::Result<VehicleMessage> m) { reply = std::move(m); });
  rig.server->stop();  // before the request is read
  ASSERT_TRUE(run_until(rig.io, [&] { return reply.has_value() && lost.has_value(); }));
  ASSERT_FALSE(reply->ok());
  EXPECT_EQ(core::ErrorCode::Closed, reply->error().code);
  EXPECT_FALSE(link->connected());
}

TEST(VehicleLink, GarbageFromTheVehicleIsReportedAndSkipped) {
  asio::io_context io;
  asio::ip::tcp::acceptor acceptor(io, {asio::ip::make_address("127.0.0.1"), 0});
  asio::ip::tcp::socket peer(io);
  acceptor.async_accept(peer, [&](const asio::error_code&) {
    std::string lines = "\x01\x02 garbage\n" + std::string(2000, 'x') + "\nanswer 99 1 0.0\n";
    asio::write(peer, asio::buffer(lines));
  });
  LinkOptions o;
  o.port = acceptor.local_endpoint().port();
  o.connect_timeout = 300ms;
  auto link = VehicleLink::create(io, o);
  std::vector<std::string> garbage;
  link->on_garbage([&](const std::string& g) { garbage.push_back(g); });
  std::optional<core::Result<protocol::Welcome>> welcome;
  link->connect([&](core::Result<protocol::Welcome> r) { welcome = std::move(r); });
  ASSERT_TRUE(run_until(io, [&] { return welcome.has_value(); }));
  EXPECT_FALSE(welcome->ok());  // no real hello answer: a timeout
  EXPECT_EQ(core::ErrorCode::Timeout, welcome->error().code);
  ASSERT_EQ(3u, garbage.size());
  EXPECT_NE(std::string::npos, garbage[1].find("over 1024 bytes"));
  EXPECT_NE(std::string::npos, garbage[2].find("no request in flight"));
}

TEST(VehicleServer, WatchdogSurfacesTheVehicleWhenTheClientDrops) {
  Rig rig;
  auto link = rig.connect();
  ASSERT_TRUE(rig.call(*link, protocol::make_ood(0, "start_network")).ok());
  ASSERT_TRUE(rig.exec(*link, "setpoint", {protocol::Value::real(1.0), protocol::Value::integer(60)}));
  ASSERT_TRUE(rig.exec(*link, "start_depth_filter"));
  ASSERT_TRUE(rig.exec(*link, "sleep", {protocol::Value::integer(1)}));
  ASSERT_TRUE(rig.exec(*link, "submerge"));
  ASSERT_TRUE(rig.exec(*link, "sleep", {protocol::Value::integer(10)}));
  ASSERT_GT(rig.sim.heave().depth_m, 0.5);
  link->close();
  ASSERT_TRUE(run_until(rig.io, [&] { return rig.sim.watchdog_tripped() && rig.sim.surface_reached(); }));
  bool said_why = false;
  for (const auto& line : rig.vehicle_log) said_why |= line.find("link dropped") != std::string::npos;
  EXPECT_TRUE(said_why);
}

TEST(VehicleServer, LinkLossSilencesTheVehicleAndItsWatchdogSurfacesIt) {
  auto scenario = vehicle::load_scenario(std::string(STRATA_SOURCE_DIR) + "/missions/tank/scenarios/link_loss.toml");
  ASSERT_TRUE(scenario.ok());
  double lost_at = *scenario.value().link_lost_at();
  Rig rig(scenario.value());
  auto link = rig.connect();
  ASSERT_TRUE(rig.call(*link, protocol::make_ood(0, "start_network")).ok());
  ASSERT_TRUE(rig.exec(*link, "setpoint", {protocol::Value::real(1.5), protocol::Value::integer(60)}));
  ASSERT_TRUE(rig.exec(*link, "start_depth_filter"));
  ASSERT_TRUE(rig.exec(*link, "sleep", {protocol::Value::integer(1)}));
  ASSERT_TRUE(rig.exec(*link, "submerge"));
  // Dive until the link goes: this request's reply is lost.
  auto r = rig.call(*link, protocol::make_exec(0, "sleep", {protocol::Value::integer(30)}), 300ms);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(core::ErrorCode::Timeout, r.error().code);
  ASSERT_TRUE(run_until(rig.io, [&] { return rig.sim.watchdog_tripped() && rig.sim.surface_reached(); }));
  // It kept diving alone for the watchdog time, then surfaced.
  std::string expected = fmt::format("{:.1f} s: watchdog: link silent for {:.1f} s: surfacing",
                                     lost_at + rig.sim.params().watchdog_s, rig.sim.params().watchdog_s);
  bool tripped_in_time = false;
  for (const auto& line : rig.vehicle_log) tripped_in_time |= line == expected;
  EXPECT_TRUE(tripped_in_time) << ::testing::PrintToString(rig.vehicle_log);
}

TEST(VehicleServer, ASilentClientTripsTheWatchdogInLockstep) {
  vehicle::VehicleParams params = vehicle::default_params();
  params.watchdog_s = 0.2;  // wall seconds of silence, in lockstep
  Rig rig(vehicle::Scenario::nominal(), protocol::ClockMode::Lockstep, params);
  auto link = rig.connect();
  ASSERT_TRUE(rig.call(*link, protocol::make_ood(0, "start_network")).ok());
  ASSERT_TRUE(run_until(
      rig.io, [&] { return rig.sim.watchdog_tripped(); }, 3000ms));
  bool said_why = false;
  for (const auto& line : rig.vehicle_log) said_why |= line.find("link silent for 0.2 s") != std::string::npos;
  EXPECT_TRUE(said_why);
}

TEST(VehicleServer, WallClockRunsOnItsOwnAndAnswersSleepLater) {
  Rig rig(vehicle::Scenario::nominal(), protocol::ClockMode::Wall);  // speed 20
  auto link = rig.connect();
  int heartbeats = 0;
  ASSERT_TRUE(rig.call(*link, protocol::make_ood(0, "start_network")).ok());
  double before = rig.sim.time_s();
  auto r = rig.call(*link, protocol::make_exec(0, "sleep", {protocol::Value::integer(2)}));
  ASSERT_TRUE(r.ok());
  const auto& done = std::get<protocol::Done>(r.value());
  EXPECT_GE(done.sim_time_s, before + 2.0 - 1e-9);
  // The simulation moved while nobody asked: that is the wall clock.
  double t = rig.sim.time_s();
  ASSERT_TRUE(run_until(rig.io, [&] { return rig.sim.time_s() > t + 0.5; }));
  (void)heartbeats;
}

// A client waiting for its `sleep` is not silent: on the wall clock the
// watchdog counts silence from the reply, as in lockstep.
TEST(VehicleServer, OnTheWallClockASleepLongerThanTheWatchdogDoesNotTripIt) {
  Rig rig(vehicle::Scenario::nominal(), protocol::ClockMode::Wall);  // speed 20
  auto link = rig.connect();
  ASSERT_TRUE(rig.call(*link, protocol::make_ood(0, "start_network")).ok());
  const double sleep_s = 2.0 * rig.sim.params().watchdog_s;
  auto r = rig.call(*link, protocol::make_exec(0, "sleep", {protocol::Value::real(sleep_s)}), 5000ms);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_FALSE(rig.sim.watchdog_tripped()) << ::testing::PrintToString(rig.vehicle_log);
  // Silent after the reply: it trips, watchdog_s after it.
  const double replied = std::get<protocol::Done>(r.value()).sim_time_s;
  ASSERT_TRUE(run_until(
      rig.io, [&] { return rig.sim.watchdog_tripped(); }, 5000ms));
  bool said = false;
  for (const auto& line : rig.vehicle_log) {
    if (line.find("link silent") == std::string::npos) continue;
    said = true;
    EXPECT_NEAR(replied + rig.sim.params().watchdog_s, std::strtod(line.c_str(), nullptr), 0.15) << line;
  }
  EXPECT_TRUE(said) << ::testing::PrintToString(rig.vehicle_log);
}

}  // namespace
}  // namespace strata::tactical
