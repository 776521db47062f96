// The IMC link's session with a DUNE vehicle: announce, the plan it starts
// and what ends it (refused, replaced, timed out, stopped, shut down), a
// silent vehicle, garbage and a second controller, the address
// (imc_link_test_support.h has the scripted peer).
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tactical/imc_link_test_support.h"

namespace strata::tactical::imc_link_tests {
namespace {

TEST(ImcLink, LearnsTheVehicleFromItsAnnounceAndStartsAFollowReferencePlanNamingItself) {
  ImcRig rig;
  rig.connect();
  EXPECT_EQ(rig.connected->value().id, kVehicleId);
  EXPECT_EQ(rig.connected->value().name, "lauv-simulator-1");
  ASSERT_TRUE(rig.vehicle.plan_start);
  const imc::PlanControl& pc = *rig.vehicle.plan_start;
  EXPECT_EQ(pc.type, imc::PlanControl::kRequest);
  EXPECT_EQ(pc.op, imc::PlanControl::kStart);
  const auto* spec = pc.arg.get_if<imc::PlanSpecification>();
  ASSERT_NE(spec, nullptr);
  ASSERT_EQ(spec->maneuvers.size(), 1u);
  const auto* follow = spec->maneuvers[0].data.get_if<imc::FollowReference>();
  ASSERT_NE(follow, nullptr);
  EXPECT_EQ(follow->control_src, rig.link->system_id());
  EXPECT_EQ(rig.link->system_id(), 0x4000 | (rig.link->local_port() & 0x1FFF));  // one id per run
  EXPECT_EQ(follow->control_ent, 1);
  EXPECT_FLOAT_EQ(follow->timeout, 10.0f);
  // The first thing after the plan: hold here (a location, always).
  ASSERT_TRUE(run_until(rig.io, [&] { return !rig.vehicle.references.empty(); }));
  EXPECT_TRUE(rig.vehicle.references.back().flags & imc::Reference::kFlagLocation);
  // Before it, the leak sensor monitored: DUNE reports a leak only then.
  bool monitored = false;
  for (const auto& p : rig.vehicle.received) {
    if (const auto* m = std::get_if<imc::MonitorEntityState>(&p.message)) {
      monitored = m->command == imc::MonitorEntityState::kCommandEnable && m->entities == "Leak Sensor - Nose";
    }
    if (std::holds_alternative<imc::PlanControl>(p.message)) break;
  }
  EXPECT_TRUE(monitored);
  // The plan was addressed to the vehicle, not broadcast (DUNE ignores 0xFFFF).
  for (const auto& p : rig.vehicle.received) {
    if (std::holds_alternative<imc::PlanControl>(p.message)) {
      EXPECT_EQ(p.header.dst, kVehicleId);
    }
  }
}

TEST(ImcLink, AVehicleThatNeverAnnouncesIsATimeoutSayingSo) {
  ImcLinkOptions o;
  o.connect_timeout = 300ms;
  ImcRig rig(o);
  rig.link->connect([&](core::Result<ImcVehicleInfo> r) { rig.connected = std::move(r); });
  ASSERT_TRUE(run_until(
      rig.io, [&] { return rig.connected.has_value(); }, 20s));
  ASSERT_FALSE(rig.connected->ok());
  EXPECT_EQ(rig.connected->error().code, core::ErrorCode::Timeout);
  EXPECT_NE(rig.connected->error().message.find("no Announce"), std::string::npos) << rig.connected->error().message;
}

TEST(ImcLink, APlanRefusedByTheVehicleIsAnErrorWithItsReason) {
  ImcRig rig;
  rig.link->connect([&](core::Result<ImcVehicleInfo> r) { rig.connected = std::move(r); });
  ASSERT_TRUE(run_until(rig.io, [&] { return !rig.vehicle.received.empty(); }));
  rig.vehicle.announce();
  rig.vehicle.state();
  ASSERT_TRUE(run_until(rig.io, [&] { return rig.vehicle.plan_start.has_value(); }));
  rig.vehicle.plan_reply(imc::PlanControl::kFailure, "vehicle in ERROR");
  ASSERT_TRUE(run_until(rig.io, [&] { return rig.connected.has_value(); }));
  ASSERT_FALSE(rig.connected->ok());
  EXPECT_EQ(rig.connected->error().message, "the IMC vehicle refused the plan: vehicle in ERROR");
}

TEST(ImcLink, APlanReplacedByAnotherControllerIsAFaultNamingBothPlans) {
  ImcRig rig;
  rig.connect();
  // Before the vehicle said it runs ours, a state naming another plan is old news.
  rig.vehicle.plan_state(imc::PlanControlState::kStateExecuting, "survey-neptus");
  EXPECT_FALSE(rig.ask("system_problem"));  // answered after the state above was read
  EXPECT_TRUE(rig.faults.empty());
  rig.vehicle.plan_state(imc::PlanControlState::kStateExecuting, rig.link->plan_id());
  rig.vehicle.plan_state(imc::PlanControlState::kStateExecuting, "survey-neptus");
  ASSERT_TRUE(run_until(rig.io, [&] { return !rig.faults.empty(); }));
  EXPECT_EQ(rig.faults[0],
            fmt::format("another controller replaced this run's plan '{}' with 'survey-neptus'", rig.link->plan_id()));
  EXPECT_EQ(rig.link->plan_id(), fmt::format("strata-{}", rig.link->local_port()));
  // Surfacing is then the other controller's call: neither a Reference nor an Abort.
  EXPECT_FALSE(rig.exec("surface"));
  EXPECT_EQ(rig.link->surface_method(), "");
}

TEST(ImcLink, AFollowReferenceTimeoutIsAFaultAndSurfaceStartsANewPlan) {
  ImcRig rig;
  rig.connect();
  ASSERT_TRUE(run_until(rig.io, [&] { return !rig.vehicle.references.empty(); }));
  rig.vehicle.follow_state(imc::FollowRefState::kStateTimeout, imc::FollowRefState::kProxFar);
  ASSERT_TRUE(run_until(rig.io, [&] { return !rig.faults.empty(); }));
  EXPECT_NE(rig.faults[0].find("FollowReference timed out"), std::string::npos);
  const std::uint16_t first = rig.vehicle.last_plan_request;
  std::optional<core::Result<protocol::VehicleMessage>> reply;
  rig.link->send(protocol::make_exec(0, "surface"), [&](auto m) { reply = std::move(m); });
  ASSERT_TRUE(run_until(rig.io, [&] { return rig.vehicle.last_plan_request != first; }));
  const std::size_t refs = rig.vehicle.references.size();
  rig.vehicle.plan_reply(imc::PlanControl::kSuccess, "plan loaded");
  ASSERT_TRUE(run_until(rig.io, [&] { return rig.vehicle.references.size() > refs; }));
  ASSERT_TRUE(rig.vehicle.references.back().z);
  EXPECT_EQ(rig.vehicle.references.back().z->value, 0.0f);
}

TEST(ImcLink, ShutdownEndsThePlanWithManDoneAndIsAnsweredWhenItEnded) {
  ImcRig rig;
  rig.connect();
  std::optional<core::Result<protocol::VehicleMessage>> reply;
  ASSERT_TRUE(run_until(rig.io, [&] { return !rig.vehicle.references.empty(); }));
  const std::size_t refs = rig.vehicle.references.size();
  rig.link->send(protocol::make_ood(0, "shutdown_network"), [&](auto m) { reply = std::move(m); });
  ASSERT_TRUE(run_until(rig.io, [&] { return rig.vehicle.references.size() > refs; }));
  EXPECT_TRUE(rig.vehicle.references.back().flags & imc::Reference::kFlagManDone);
  EXPECT_FALSE(rig.ask("system_problem"));  // a state has passed ...
  EXPECT_FALSE(reply.has_value());          // ... and the plan still runs: no answer yet
  rig.vehicle.plan_reply(imc::PlanControl::kSuccess, "plan completed");
  ASSERT_TRUE(run_until(rig.io, [&] { return reply.has_value(); }));
  ASSERT_TRUE(reply->ok());
  EXPECT_TRUE(std::get<protocol::Done>(reply->value()).success);
  EXPECT_FALSE(rig.link->plan_running());
}

TEST(ImcLink, ASilentVehicleIsLostAndItsCallsFail) {
  ImcLinkOptions o;
  o.lost_after = 200ms;
  ImcRig rig(o);
  rig.connect();
  std::optional<core::Result<protocol::VehicleMessage>> reply;
  rig.link->send(protocol::make_ask(0, "depth_reached"), [&](auto m) { reply = std::move(m); });
  // Only wall time passes: the vehicle says nothing more.
  ASSERT_TRUE(run_until(
      rig.io, [&] { return rig.lost.has_value() && reply.has_value(); }, 30s));
  EXPECT_EQ(rig.lost->code, core::ErrorCode::Closed);
  EXPECT_EQ(rig.lost->message, "no EstimatedState from the IMC vehicle for 200 ms");
  ASSERT_FALSE(reply->ok());
  EXPECT_EQ(reply->error().code, core::ErrorCode::Closed);
}

TEST(ImcLink, GarbageAndOtherSystemsAreCountedNeverUsed) {
  ImcRig rig;
  rig.connect();
  const std::uint64_t used = rig.link->counts().used;
  const std::uint64_t received = rig.link->counts().received;
  rig.vehicle.send_raw({0xFE, 0x54, 1, 2, 3});  // truncated
  imc::Packet heartbeat{{}, imc::Message(imc::Heartbeat{})};
  heartbeat.header.src = kVehicleId;
  std::vector<std::uint8_t> bad = imc::encode(heartbeat).value();
  bad.back() ^= 0xFF;  // CRC
  rig.vehicle.send_raw(bad);
  // Another system on the same address (a second vehicle's id): its state must not move ours.
  rig.vehicle.send(imc::Message(imc::VehicleState{}), 0x0022);
  // A message a controller does not read (EntityState, 53 Hz on DUNE).
  rig.vehicle.send(imc::Message(imc::EntityState{}));
  ASSERT_TRUE(run_until(rig.io, [&] { return rig.link->counts().received >= received + 4; }));
  const ImcCounts& c = rig.link->counts();
  EXPECT_EQ(c.dropped.total(), 2u);
  EXPECT_EQ(c.other_sources, 1u);
  EXPECT_EQ(c.filtered, 1u);
  EXPECT_EQ(c.used, used);
  EXPECT_NE(imc_summary(c).find("1 from others, 2 dropped ("), std::string::npos) << imc_summary(c);
}

TEST(ImcLink, AFloodOfGarbageAndASecondControllerAreCountedAndTheCallsGoOn) {
  ImcLinkOptions o;
  o.lost_after = std::chrono::minutes(1);  // no state comes while the flood is sent: not a lost vehicle
  ImcRig rig(o);
  rig.connect();
  // A second controller on its own socket: everything it sends is another
  // system's, its PlanControl included.
  asio::ip::udp::socket other(rig.io, asio::ip::udp::endpoint(asio::ip::make_address("127.0.0.1"), 0));
  const asio::ip::udp::endpoint link_at(asio::ip::make_address("127.0.0.1"), rig.link->local_port());
  imc::PlanControl start;
  start.type = imc::PlanControl::kRequest;
  start.plan_id = "neptus";
  imc::Packet theirs{{}, imc::Message(start)};
  theirs.header.src = 0x4100;
  const auto their_bytes = imc::encode(theirs).value();
  // Garbage from the vehicle's own address: every kind of bad packet.
  auto good = imc::encode(imc::Packet{{0, 0, 0, kVehicleId}, imc::Message(imc::Heartbeat{})}).value();
  std::vector<std::vector<std::uint8_t>> garbage{{0x01}, std::vector<std::uint8_t>(20, 0xAB), good, good, good};
  garbage[2].back() ^= 0x5A;     // CRC
  garbage[3][4] = 0x7F;          // size bigger than the datagram
  garbage[4][2] = 0x39;          // an id no one knows (0x0039... at the header)
  constexpr int kRounds = 2000;  // 10,000 bad datagrams and 2,000 from the other controller
  const std::uint64_t received = rig.link->counts().received;
  const ImcCounts before = rig.link->counts();
  int answered = 0;
  for (int round = 0; round < kRounds; ++round) {
    for (const auto& g : garbage) rig.vehicle.send_raw(g);
    other.send_to(asio::buffer(their_bytes), link_at);
    rig.io.restart();
    rig.io.poll();  // the link reads as it comes, as its loop does
    if (round % 200 == 0) {
      // Still answered, in between (a state lost in a full socket buffer: the next one answers).
      auto r = rig.call(protocol::make_ask(0, "depth_filter_off"), 20);
      answered += r.ok() && std::get<protocol::Answer>(r.value()).value ? 1 : 0;
    }
  }
  EXPECT_EQ(answered, kRounds / 200);
  // UDP may drop some of a flood in the kernel; every datagram that arrives
  // is accounted for: used, filtered at its header, another system's, or
  // dropped under its reason.
  const ImcCounts& c = rig.link->counts();
  EXPECT_EQ(c.received - received, (c.used - before.used) + (c.filtered - before.filtered) +
                                       (c.other_sources - before.other_sources) +
                                       (c.dropped.total() - before.dropped.total()));
  EXPECT_GT(c.other_sources - before.other_sources, 0u);
  for (imc::Drop d : {imc::Drop::Truncated, imc::Drop::BadCrc}) {
    EXPECT_GT(c.dropped.by_reason[static_cast<std::size_t>(d)], 0u) << imc::drop_name(d);
  }
  EXPECT_GT(c.filtered + c.dropped.by_reason[static_cast<std::size_t>(imc::Drop::Truncated)] +
                c.dropped.by_reason[static_cast<std::size_t>(imc::Drop::BadSize)],
            0u);  // the size and the unknown id: seen at the header
  EXPECT_TRUE(rig.faults.empty());
  EXPECT_TRUE(rig.link->plan_running());
  EXPECT_TRUE(rig.exec("goto_depth", {protocol::Value::integer(1)}));
}

TEST(ImcLink, APlanStoppedOutsideTheRunIsAFaultAndSteeringThenSaysZero) {
  ImcRig rig;
  rig.connect();
  rig.vehicle.plan_state(imc::PlanControlState::kStateExecuting, rig.link->plan_id());
  rig.vehicle.plan_state(imc::PlanControlState::kStateReady, rig.link->plan_id());  // an operator's STOP
  ASSERT_TRUE(run_until(rig.io, [&] { return !rig.faults.empty(); }));
  EXPECT_NE(rig.faults[0].find("was stopped outside the run"), std::string::npos) << rig.faults[0];
  EXPECT_FALSE(rig.link->plan_running());
  EXPECT_FALSE(rig.exec("goto_depth", {protocol::Value::integer(2)}));  // nothing takes it: 0, not 1
}

TEST(ImcLink, AStartWhoseReplyWasLostIsConfirmedByThePlansState) {
  ImcRig rig;
  rig.link->connect([&](core::Result<ImcVehicleInfo> r) { rig.connected = std::move(r); });
  ASSERT_TRUE(run_until(rig.io, [&] { return !rig.vehicle.received.empty(); }));
  rig.vehicle.announce();
  rig.vehicle.state();
  ASSERT_TRUE(run_until(rig.io, [&] { return rig.vehicle.plan_start.has_value(); }));
  // No PlanControl reply (lost on the way); the periodic state names the plan.
  rig.vehicle.plan_state(imc::PlanControlState::kStateExecuting, rig.vehicle.plan_start->plan_id);
  ASSERT_TRUE(run_until(rig.io, [&] { return rig.connected.has_value(); }));
  ASSERT_TRUE(rig.connected->ok());
  EXPECT_TRUE(rig.link->plan_running());
}

// The Heartbeats the link sent the vehicle, by their stamps (run time).
std::vector<double> heartbeats_sent(const ScriptedVehicle& v) {
  std::vector<double> out;
  for (const auto& p : v.received) {
    if (std::holds_alternative<imc::Heartbeat>(p.message)) out.push_back(p.header.timestamp - kEpoch);
  }
  return out;
}

// `strata vehicle --imc --lockstep` (docs/imc.md, "Lockstep"): the vehicle's
// Heartbeat ends a cycle; the link answers it once, stamped with it, when
// what the cycle started is done: not while a Hold is alive.
TEST(ImcLink, ALockstepVehicleIsAnsweredOncePerCycleWhenTheWorkIsDone) {
  ImcRig rig;
  rig.connect(fmt::format("imc+udp://127.0.0.1:6002/;{}", imc::kLockstepService));
  EXPECT_TRUE(rig.link->lockstep());
  // Before the vehicle's Announce the link heartbeats on the wall clock
  // (none unless the connect took a second); from it on, only answers.
  const std::size_t before = heartbeats_sent(rig.vehicle).size();
  rig.vehicle.state();
  rig.vehicle.send(imc::Heartbeat{});  // the cycle's end
  rig.vehicle.send(imc::Heartbeat{});  // twice at one time: one answer
  ASSERT_TRUE(run_until(rig.io, [&] { return heartbeats_sent(rig.vehicle).size() > before; }));
  EXPECT_NEAR(rig.vehicle.t_s, heartbeats_sent(rig.vehicle).back(), 1e-5);
  // A Hold (an outcome queued for the mission) keeps the answer back.
  auto hold = rig.link->hold();
  rig.vehicle.state();
  rig.vehicle.send(imc::Heartbeat{});
  run_until(
      rig.io, [] { return false; }, 100ms);
  EXPECT_EQ(before + 1, heartbeats_sent(rig.vehicle).size());
  hold.release();
  ASSERT_TRUE(run_until(rig.io, [&] { return heartbeats_sent(rig.vehicle).size() == before + 2; }));
  EXPECT_NEAR(rig.vehicle.t_s, heartbeats_sent(rig.vehicle).back(), 1e-5);
  run_until(
      rig.io, [] { return false; }, 50ms);
  EXPECT_EQ(before + 2, heartbeats_sent(rig.vehicle).size());
}

// DUNE offers no lockstep, and a service only like it is not it: the link
// then heartbeats on the wall clock and answers no cycle.
TEST(ImcLink, OnlyTheLockstepServiceItselfMakesALockstepLink) {
  for (const std::string services :
       {"imc+udp://127.0.0.1:6002/", "strata://lockstep2", "xstrata://lockstep;imc+udp://127.0.0.1:6002/", ""}) {
    SCOPED_TRACE(services);
    ImcRig rig;
    rig.connect(services);
    EXPECT_FALSE(rig.link->lockstep());
  }
  ImcRig rig;
  rig.connect(fmt::format("{};imc+udp://127.0.0.1:6002/", imc::kLockstepService));
  EXPECT_TRUE(rig.link->lockstep());
}

TEST(ImcLinkAddress, ParsesHostPortAndAnOptionalId) {
  auto a = parse_imc_vehicle("imc://127.0.0.1:6002");
  ASSERT_TRUE(a.ok());
  EXPECT_EQ(a.value().host, "127.0.0.1");
  EXPECT_EQ(a.value().port, 6002);
  EXPECT_FALSE(a.value().vehicle_id);
  auto b = parse_imc_vehicle("imc://localhost:6002/0x00D1");
  ASSERT_TRUE(b.ok());
  EXPECT_EQ(b.value().vehicle_id, 0x00D1);
  EXPECT_EQ(parse_imc_vehicle("imc://localhost:6002/209").value().vehicle_id, 209);
  for (const char* bad : {"imc://", "imc://host", "imc://:6002", "imc://h:0", "imc://h:65536", "imc://h:60x",
                          "imc://h:6002/", "imc://h:6002/0", "imc://h:6002/0xFFFF", "imc://h:6002/zz", "h:6002"}) {
    auto r = parse_imc_vehicle(bad);
    ASSERT_FALSE(r.ok()) << bad;
    EXPECT_EQ(r.error().code, core::ErrorCode::InvalidInput) << bad;
    EXPECT_NE(r.error().message.find("expected imc://HOST:PORT"), std::string::npos) << r.error().message;
  }
}

}  // namespace
}  // namespace strata::tactical::imc_link_tests
