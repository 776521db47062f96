// `strata vehicle --imc` spoken to by a scripted IMC peer over loopback UDP:
// announce and the streams, the plan and who may steer it, silence, a leak,
// abort and garbage (imc_server_test_support.h has the rig and the peer).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <thread>
#include <vector>

#include "vehicle/imc_server_test_support.h"

namespace strata::vehicle::imc_server_tests {
namespace {

TEST(ImcVehicleServer, SilentUntilAPeerAnnouncesThenStreams) {
  Rig rig;
  TestPeer peer(rig.port());
  peer.send(imc::Heartbeat{});
  peer.send(start_plan(1, 0));
  peer.send_raw({1, 2, 3});
  peer.announce();
  auto a = peer.wait_for<imc::Announce>();
  ASSERT_TRUE(a);
  EXPECT_EQ("phoenix-sim", a->sys_name);
  EXPECT_EQ(imc::Announce::kSysTypeUuv, a->sys_type);
  EXPECT_NE(std::string::npos, a->services.find("imc+udp://127.0.0.1:"));
  // Nothing came before the Announce: what was sent unannounced was dropped unread.
  const auto first = peer.packets().front();
  EXPECT_TRUE(std::holds_alternative<imc::Announce>(first.message));
  EXPECT_EQ(kVehicleId, first.header.src);
  EXPECT_EQ(0, first.header.src_ent);
  EXPECT_GE(first.header.timestamp, kImcEpochS);
  auto c = rig.counts();
  EXPECT_EQ(4u, c.datagrams);
  EXPECT_EQ(2u, c.dropped.by_reason[static_cast<std::size_t>(imc::Drop::Filtered)]);
  EXPECT_EQ(1u, c.dropped.by_reason[static_cast<std::size_t>(imc::Drop::Truncated)]);
  EXPECT_EQ(0u, c.accepted);

  ASSERT_TRUE(peer.wait_for<imc::Heartbeat>());
  ASSERT_TRUE(peer.wait_for<imc::GpsFix>());
  auto vs = peer.wait_for<imc::VehicleState>();
  ASSERT_TRUE(vs);
  EXPECT_EQ(imc::VehicleState::kOpModeService, vs->op_mode);
  auto pcs = peer.wait_for<imc::PlanControlState>();
  ASSERT_TRUE(pcs);
  EXPECT_EQ(imc::PlanControlState::kStateReady, pcs->state);
  EXPECT_TRUE(peer.wait_for<imc::EstimatedState>());
  EXPECT_EQ(0u, peer.count<imc::PlanControl>());
  EXPECT_EQ(0u, peer.undecodable());
  EXPECT_EQ(1u, rig.peers());
}

TEST(ImcVehicleServer, EstimatedStateEveryCycleAndTheSlowerStreamsAtTheirRates) {
  Rig rig;
  TestPeer peer(rig.port());
  peer.announce();
  ASSERT_TRUE(peer.wait_for<imc::Announce>());
  peer.cycles(42);
  const auto packets = peer.packets();
  std::vector<std::size_t> est;
  for (std::size_t i = 0; i < packets.size(); ++i) {
    if (std::holds_alternative<imc::EstimatedState>(packets[i].message)) est.push_back(i);
  }
  ASSERT_GE(est.size(), 42u);
  // 40 cycles (4 simulated seconds) from the first EstimatedState on.
  std::size_t vs = 0, gps = 0, hb = 0, pcs = 0, nu = 0;
  for (std::size_t i = est[0] + 1; i < est[40]; ++i) {
    const auto& m = packets[i].message;
    vs += std::holds_alternative<imc::VehicleState>(m);
    gps += std::holds_alternative<imc::GpsFix>(m);
    hb += std::holds_alternative<imc::Heartbeat>(m);
    pcs += std::holds_alternative<imc::PlanControlState>(m);
    nu += std::holds_alternative<imc::NavigationUncertainty>(m);
  }
  EXPECT_EQ(8u, vs);
  EXPECT_EQ(8u, pcs);
  EXPECT_EQ(4u, gps);
  EXPECT_EQ(4u, hb);
  EXPECT_EQ(40u, nu);  // every cycle, before its EstimatedState
  EXPECT_TRUE(std::holds_alternative<imc::NavigationUncertainty>(packets[est[1] - 1].message));
  // Simulated time in the header, whatever the speed and the machine's load.
  EXPECT_NEAR(4.0, packets[est[40]].header.timestamp - packets[est[0]].header.timestamp, 1e-6);
}

TEST(ImcVehicleServer, PlanStartIsAnsweredAndOnlyTheControlSourceSteers) {
  Rig rig;
  TestPeer peer(rig.port());
  TestPeer other(rig.port(), 0x4002);
  peer.announce();
  other.announce();
  ASSERT_TRUE(peer.wait_for<imc::Announce>());
  ASSERT_TRUE(other.wait_for<imc::Announce>());
  peer.send(start_plan(7, 0), imc::kNullId);  // 0xFFFF: ignored, as DUNE does
  peer.send(start_plan(8, 0), imc::kAnyVehicle);
  auto loaded = peer.wait_for<imc::PlanControl>();
  ASSERT_TRUE(loaded);
  EXPECT_EQ(imc::PlanControl::kSuccess, loaded->type);
  EXPECT_EQ(8, loaded->request_id);
  EXPECT_EQ("strata", loaded->plan_id);
  EXPECT_EQ("plan loaded", loaded->info);
  auto executing = peer.wait_for<imc::PlanControl>();
  ASSERT_TRUE(executing);
  EXPECT_EQ("executing maneuver", executing->info);
  EXPECT_TRUE(peer.wait_for<imc::PlanControlState>(
      [](const auto& s) { return s.state == imc::PlanControlState::kStateExecuting && s.plan_id == "strata"; }));
  EXPECT_TRUE(
      peer.wait_for<imc::VehicleState>([](const auto& s) { return s.op_mode == imc::VehicleState::kOpModeManeuver; }));
  auto wait = peer.wait_for<imc::FollowRefState>();
  ASSERT_TRUE(wait);
  EXPECT_EQ(imc::FollowRefState::kStateWait, wait->state);
  EXPECT_EQ(imc::FollowRefState::kProxFar, wait->proximity);
  EXPECT_EQ(kPeerId, wait->control_src);

  // A Reference from another system is ignored; the controller's is answered once.
  auto here = peer.wait_for<imc::EstimatedState>();
  ASSERT_TRUE(here);
  other.send(reference_here(*here, 2.0));
  peer.send(reference_here(*here, 2.0));
  auto answer = peer.wait_for<imc::FollowRefState>();
  ASSERT_TRUE(answer);
  ASSERT_TRUE(answer->reference);
  EXPECT_EQ(reference_here(*here, 2.0), *answer->reference);
  EXPECT_TRUE(answer->proximity & imc::FollowRefState::kProxXyNear);
  EXPECT_FALSE(answer->proximity & imc::FollowRefState::kProxZNear);
  EXPECT_EQ(imc::FollowRefState::kStateElevator, answer->state);
  const auto vc = rig.vehicle_counts();
  EXPECT_EQ(1u, vc.references);
  EXPECT_EQ(1u, vc.references_ignored);
  EXPECT_EQ(1u, vc.requests_ignored);
  EXPECT_EQ(2u, peer.count<imc::FollowRefState>());

  // STOP: answered, the plan ends, the motors stop.
  imc::PlanControl stop;
  stop.type = imc::PlanControl::kRequest;
  stop.op = imc::PlanControl::kStop;
  stop.request_id = 9;
  stop.plan_id = "strata";
  peer.send(stop);
  auto stopped = peer.wait_for<imc::PlanControl>();
  ASSERT_TRUE(stopped);
  EXPECT_EQ(imc::PlanControl::kSuccess, stopped->type);
  EXPECT_EQ(9, stopped->request_id);
  EXPECT_TRUE(peer.wait_for<imc::VehicleState>(
      [](const auto& s) { return s.op_mode == imc::VehicleState::kOpModeService && s.control_loops == 0; }));
}

TEST(ImcVehicleServer, SilenceBeyondTheTimeoutEndsThePlanAndStopsTheMotors) {
  Rig rig;
  TestPeer peer(rig.port());
  start(peer, 2.0f);
  auto timeout =
      peer.wait_for<imc::FollowRefState>([](const auto& s) { return s.state == imc::FollowRefState::kStateTimeout; });
  ASSERT_TRUE(timeout);
  auto failed = peer.wait_for<imc::PlanControl>();
  ASSERT_TRUE(failed);
  EXPECT_EQ(imc::PlanControl::kFailure, failed->type);
  EXPECT_EQ("reference source timed out", failed->info);
  EXPECT_EQ(11, failed->request_id);
  EXPECT_TRUE(peer.wait_for<imc::PlanControlState>([](const auto& s) {
    return s.state == imc::PlanControlState::kStateReady &&
           s.last_outcome == imc::PlanControlState::kLastOutcomeFailure;
  }));
  auto vs = peer.wait_for<imc::VehicleState>();
  ASSERT_TRUE(vs);
  EXPECT_EQ(imc::VehicleState::kOpModeService, vs->op_mode);
  EXPECT_EQ(0u, vs->control_loops);
  // Timed out 2 simulated seconds after the start, whatever the machine's load.
  const auto packets = peer.packets();
  double start_t = 0, timeout_t = 0;
  for (const auto& p : packets) {
    if (const auto* pc = std::get_if<imc::PlanControl>(&p.message); pc && pc->info == "plan loaded") {
      start_t = p.header.timestamp;
    }
    if (const auto* s = std::get_if<imc::FollowRefState>(&p.message);
        s && s->state == imc::FollowRefState::kStateTimeout) {
      timeout_t = p.header.timestamp;
    }
  }
  EXPECT_NEAR(2.0, timeout_t - start_t, 0.11);
}

TEST(ImcVehicleServer, ALeakIsAnErrorAndFailsThePlan) {
  Scenario s = Scenario::nominal();
  Fault leak;
  leak.kind = FaultKind::Leak;
  leak.at_s = 3.0;
  s.faults.push_back(leak);
  Rig rig(s);
  TestPeer peer(rig.port());
  start(peer);
  // At the leak the plan fails, then the states say why.
  auto failed = peer.wait_for<imc::PlanControl>([](const auto& pc) { return pc.type == imc::PlanControl::kFailure; });
  ASSERT_TRUE(failed);
  EXPECT_EQ(11, failed->request_id);
  EXPECT_EQ("Leak Sensor - Nose: leak detected", failed->info);
  EXPECT_TRUE(peer.wait_for<imc::PlanControlState>([](const auto& p) {
    return p.state == imc::PlanControlState::kStateBlocked &&
           p.last_outcome == imc::PlanControlState::kLastOutcomeFailure;
  }));
  auto error =
      peer.wait_for<imc::VehicleState>([](const auto& v) { return v.op_mode == imc::VehicleState::kOpModeError; });
  ASSERT_TRUE(error);
  EXPECT_EQ(1, error->error_count);
  EXPECT_EQ("Leak Sensor - Nose", error->error_ents);
  EXPECT_EQ("Leak Sensor - Nose: leak detected", error->last_error);
  // A plan started in error fails at once.
  peer.send(start_plan(12, 0));
  auto again = peer.wait_for<imc::PlanControl>(
      [](const auto& pc) { return pc.request_id == 12 && pc.type == imc::PlanControl::kFailure; });
  EXPECT_TRUE(again);
}

TEST(ImcVehicleServer, AbortFailsThePlanAndTheVehicleSurfacesItself) {
  Rig rig;
  TestPeer peer(rig.port());
  start(peer);
  dive(peer, 2.0);
  peer.send(imc::Abort{});
  auto failed = peer.wait_for<imc::PlanControl>([](const auto& pc) { return pc.type == imc::PlanControl::kFailure; });
  ASSERT_TRUE(failed);
  EXPECT_EQ(11, failed->request_id);
  EXPECT_EQ("got abort request", failed->info);
  auto error =
      peer.wait_for<imc::VehicleState>([](const auto& v) { return v.op_mode == imc::VehicleState::kOpModeError; });
  ASSERT_TRUE(error);
  EXPECT_EQ("got abort request", error->last_error);
  EXPECT_TRUE(error->control_loops & imc::VehicleState::kLoopDepth);  // the surface law
  EXPECT_TRUE(
      peer.wait_for<imc::VehicleState>([](const auto& v) { return v.op_mode == imc::VehicleState::kOpModeService; }));
  EXPECT_TRUE(peer.wait_for<imc::EstimatedState>([](const auto& s) { return s.depth < 0.2; }));
  // No plan: a Reference now is ignored.
  auto here = peer.wait_for<imc::EstimatedState>();
  ASSERT_TRUE(here);
  const auto refs_before = peer.count<imc::FollowRefState>();
  // Counted once the vehicle has read it (a count after three cycles the
  // peer had already received missed it at a load of 6).
  send_and_settle(rig, peer, reference_here(*here, 2.0));
  EXPECT_EQ(refs_before, peer.count<imc::FollowRefState>());
  EXPECT_EQ(1u, rig.vehicle_counts().references_ignored);
}

// `strata vehicle --imc --lockstep` (docs/imc.md, "Lockstep"): it offers
// the service, ends each cycle with a Heartbeat, and runs the next one only
// when a Heartbeat stamped with that cycle's time (or later) comes.
TEST(ImcVehicleServer, InLockstepEachCycleWaitsForAHeartbeatStampedWithIt) {
  Rig rig(Scenario::nominal(), 16, std::chrono::hours(1));  // no cycle without an answer
  TestPeer peer(rig.port());
  peer.announce();
  auto a = peer.wait_for<imc::Announce>();
  ASSERT_TRUE(a);
  EXPECT_NE(std::string::npos, a->services.find(";strata://lockstep")) << a->services;
  ASSERT_TRUE(peer.wait_for<imc::EstimatedState>());
  ASSERT_TRUE(peer.wait_for<imc::Heartbeat>());
  const double first = rig.timestamp();
  // A Heartbeat stamped with another time is no answer (an earlier cycle,
  // a later one, a console's on the wall clock), nor is a stamp that is no
  // time: read, and no cycle ran.
  const auto read = rig.counts().datagrams;
  for (const double stamp : {first - 0.1, first + 0.1, 1.79e9, std::numeric_limits<double>::quiet_NaN(),
                             std::numeric_limits<double>::infinity()}) {
    peer.send(imc::Heartbeat{}, kVehicleId, stamp);
  }
  ASSERT_TRUE(rig.wait_read(read + 5));
  EXPECT_DOUBLE_EQ(first, rig.timestamp());
  for (int cycle = 1; cycle <= 3; ++cycle) {
    peer.send(imc::Heartbeat{}, kVehicleId, rig.timestamp());
    ASSERT_TRUE(peer.wait_past(first + 0.1 * (cycle - 1) + 1e-3));
    EXPECT_NEAR(first + 0.1 * cycle, rig.timestamp(), 1e-6);
  }
  EXPECT_EQ(0u, rig.counts().lockstep_waits_ended);
}

// While a plan runs, its controller paces the vehicle: another peer's
// answer, even stamped right, is not one.
TEST(ImcVehicleServer, InLockstepOnlyThePlansControllerAnswersWhileItRuns) {
  Rig rig(Scenario::nominal(), 16, std::chrono::hours(1));
  TestPeer peer(rig.port());
  TestPeer other(rig.port(), 0x4002);
  other.announce();
  ASSERT_TRUE(other.wait_for<imc::Announce>());
  start(peer);  // its plan, steered by it
  const auto read = rig.counts().datagrams;
  const double waiting = rig.timestamp();
  other.send(imc::Heartbeat{}, kVehicleId, waiting);
  ASSERT_TRUE(rig.wait_read(read + 1));
  EXPECT_DOUBLE_EQ(waiting, rig.timestamp());
  peer.send(imc::Heartbeat{}, kVehicleId, waiting);
  ASSERT_TRUE(peer.wait_past(waiting + 1e-3));
  EXPECT_NEAR(waiting + 0.1, rig.timestamp(), 1e-6);
}

// Announced to a lockstep vehicle, its first cycle read to its end: the
// time the vehicle now waits at (0 if that did not come).
double first_lockstep_cycle(Rig& rig, TestPeer& peer) {
  peer.announce();
  if (!peer.wait_for<imc::EstimatedState>() || !peer.wait_for<imc::Heartbeat>()) return 0;
  return rig.timestamp();
}

// A thousand right answers at once (a flood, or a controller gone wrong)
// are one cycle: the vehicle waits again after it.
TEST(ImcVehicleServer, InLockstepAThousandAnswersToOneCycleRunOneCycle) {
  Rig rig(Scenario::nominal(), 16, std::chrono::hours(1));
  TestPeer peer(rig.port());
  const double waiting = first_lockstep_cycle(rig, peer);
  ASSERT_GT(waiting, 0);
  // In tens of a hundred, each read before the next: a hundred small
  // datagrams fit the vehicle's socket buffer, so none is dropped unread.
  const auto read = rig.counts().datagrams;
  for (int batch = 1; batch <= 10; ++batch) {
    for (int i = 0; i < 100; ++i) peer.send(imc::Heartbeat{}, kVehicleId, waiting);
    ASSERT_TRUE(rig.wait_read(read + 100 * static_cast<std::uint64_t>(batch)));
  }
  EXPECT_NEAR(waiting + 0.1, rig.timestamp(), 1e-6);
  EXPECT_EQ(0u, rig.counts().lockstep_waits_ended);
}

// A second run on the same vehicle: the first controller (gone, or silent)
// never answers its last cycle; a new one is not kept waiting for it.
TEST(ImcVehicleServer, InLockstepANewControllerDoesNotWaitForTheLastOnesAnswer) {
  Rig rig(Scenario::nominal(), 16, std::chrono::hours(1));
  TestPeer first(rig.port());
  const double waiting = first_lockstep_cycle(rig, first);
  ASSERT_GT(waiting, 0);
  TestPeer second(rig.port(), 0x4002);
  second.announce();
  ASSERT_TRUE(second.wait_for<imc::Announce>());
  ASSERT_TRUE(second.wait_for<imc::EstimatedState>());
  EXPECT_NEAR(waiting + 0.1, rig.timestamp(), 1e-6);  // one cycle, then it waits for an answer
  EXPECT_EQ(0u, rig.counts().lockstep_waits_ended);
}

// A controller that never answers (not a Strata link) still gets a cycle
// each lockstep_wait of wall time, counted.
TEST(ImcVehicleServer, InLockstepAnUnansweredCycleEndsAfterItsWait) {
  Rig rig(Scenario::nominal(), 16, std::chrono::milliseconds(10));
  TestPeer peer(rig.port());
  peer.announce();
  ASSERT_TRUE(peer.wait_for<imc::Announce>());
  peer.cycles(4);
  EXPECT_GE(rig.counts().lockstep_waits_ended, 3u);
}

TEST(ImcVehicleServer, GarbageIsCountedAndDroppedAndTheVehicleGoesOn) {
  Rig rig(Scenario::nominal(), 2);
  TestPeer peer(rig.port());
  TestPeer stranger(rig.port(), 0x5000);
  stranger.send(imc::Heartbeat{});  // not announced: filtered
  peer.announce();
  ASSERT_TRUE(peer.wait_for<imc::Announce>());
  imc::Packet hb;
  hb.header.src = kPeerId;
  hb.message = imc::Heartbeat{};
  auto good = imc::encode(hb).value();
  auto bad_crc = good;
  bad_crc.back() ^= 0xFF;
  auto unknown = good;
  unknown[2] = 0x0F;  // mgid 9999
  unknown[3] = 0x27;
  const std::uint16_t crc = crc16_ibm(unknown.data(), imc::kHeaderBytes);
  unknown[imc::kHeaderBytes] = static_cast<std::uint8_t>(crc & 0xFF);
  unknown[imc::kHeaderBytes + 1] = static_cast<std::uint8_t>(crc >> 8);
  auto longer = good;
  longer.push_back(0);
  peer.send_raw({0xFE});
  peer.send_raw(std::vector<std::uint8_t>(60000, 0xAB));
  peer.send_raw(bad_crc);
  peer.send_raw(unknown);
  peer.send_raw(longer);
  peer.send(imc::EntityList{});  // decodes, but nothing to act on
  // Two more peers: the cap is 2.
  TestPeer second(rig.port(), 0x4002);
  TestPeer third(rig.port(), 0x4003);
  second.announce();
  ASSERT_TRUE(second.wait_for<imc::Announce>());
  third.announce();
  // Every datagram above has been read once a request sent after them is answered.
  peer.send(start_plan(20, 0));
  ASSERT_TRUE(peer.wait_for<imc::PlanControl>([](const auto& pc) { return pc.request_id == 20; }));
  const auto c = rig.counts();
  const auto reason = [&](imc::Drop d) { return c.dropped.by_reason[static_cast<std::size_t>(d)]; };
  EXPECT_EQ(1u, reason(imc::Drop::Filtered));
  EXPECT_EQ(1u, reason(imc::Drop::Truncated));
  EXPECT_EQ(1u, reason(imc::Drop::BadSync));
  EXPECT_EQ(1u, reason(imc::Drop::BadCrc));
  EXPECT_EQ(1u, reason(imc::Drop::UnknownId));
  EXPECT_EQ(1u, reason(imc::Drop::BadSize));
  EXPECT_EQ(1u, c.not_acted_on);
  EXPECT_EQ(1u, c.peers_refused);
  EXPECT_EQ(2u, rig.peers());
  EXPECT_TRUE(peer.wait_for<imc::EstimatedState>());
  second.cycles(2);
  EXPECT_EQ(0u, third.count<imc::Announce>());
  EXPECT_EQ(0u, third.received_now());
}

}  // namespace
}  // namespace strata::vehicle::imc_server_tests
