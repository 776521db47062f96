// `strata vehicle --imc` steered by References: to a depth, north, to the
// surface, the GPS fix at the surface, and the frame IMC's x and y are in
// (imc_server_test_support.h has the rig and the peer).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <optional>
#include <thread>
#include <vector>

#include "vehicle/imc_server_test_support.h"

namespace strata::vehicle::imc_server_tests {
namespace {

TEST(ImcVehicleServer, AReferenceToDepthGetsZNearThenManDoneCompletesThePlan) {
  Rig rig;
  TestPeer peer(rig.port());
  start(peer);
  const auto there = dive(peer, 2.0);
  peer.send(reference_here(there, 2.0));
  auto near = peer.wait_for<imc::FollowRefState>([](const auto& s) { return s.reference.has_value(); });
  ASSERT_TRUE(near);
  EXPECT_EQ(imc::FollowRefState::kProxXyNear | imc::FollowRefState::kProxZNear, near->proximity);
  EXPECT_EQ(imc::FollowRefState::kStateLoiter, near->state);
  // Exactly one FollowRefState per Reference, and the one at the start.
  EXPECT_EQ(3u, peer.count<imc::FollowRefState>());

  peer.send(reference_here(there, 2.0, imc::Reference::kFlagManDone));
  auto done = peer.wait_for<imc::PlanControl>([](const auto& pc) { return pc.type != imc::PlanControl::kRequest; });
  ASSERT_TRUE(done);
  EXPECT_EQ(imc::PlanControl::kSuccess, done->type);
  EXPECT_EQ("plan completed", done->info);
  EXPECT_EQ(11, done->request_id);
  EXPECT_TRUE(peer.wait_for<imc::PlanControlState>([](const auto& s) {
    return s.state == imc::PlanControlState::kStateReady &&
           s.last_outcome == imc::PlanControlState::kLastOutcomeSuccess;
  }));
  EXPECT_TRUE(
      peer.wait_for<imc::VehicleState>([](const auto& s) { return s.op_mode == imc::VehicleState::kOpModeService; }));
}

TEST(ImcVehicleServer, AReferenceNorthDrivesNorthUntilXyNear) {
  Scenario s = Scenario::nominal();
  s.world.open_water = true;
  VehicleParams p = default_params();
  Rig rig(s);
  TestPeer peer(rig.port());
  start(peer);
  auto here = peer.wait_for<imc::EstimatedState>();
  ASSERT_TRUE(here);
  imc::EstimatedState goal = *here;
  goal.x += 40.0f;  // IMC x: north
  auto ref = reference_here(goal, 0.0);
  ref.flags = imc::Reference::kFlagLocation | imc::Reference::kFlagSpeed;
  ref.speed = imc::DesiredSpeed{5.0, imc::DesiredSpeed::kSpeedUnitsMetersPs};  // clamped to the top speed
  peer.send(ref);
  auto going = peer.wait_for<imc::FollowRefState>([](const auto& f) { return f.reference.has_value(); });
  ASSERT_TRUE(going);
  EXPECT_EQ(imc::FollowRefState::kStateGoto, going->state);
  // No z asked: z is near; far from the point.
  EXPECT_EQ(imc::FollowRefState::kProxZNear, going->proximity);
  auto near = peer.wait_for<imc::EstimatedState>([&](const auto& e) { return e.x > here->x + 30.0f; });
  ASSERT_TRUE(near);
  EXPECT_NEAR(here->y, near->y, 5.0);  // not east or west
  EXPECT_LE(near->u, p.top_speed_mps() + 1e-3);
  peer.send(ref);
  auto arrived = peer.wait_for<imc::FollowRefState>([](const auto& f) { return f.reference.has_value(); });
  ASSERT_TRUE(arrived);
  EXPECT_TRUE(arrived->proximity & imc::FollowRefState::kProxXyNear);
  EXPECT_EQ(2u, rig.vehicle_counts().clamped);  // both References' speeds
}

TEST(ImcVehicleServer, ASurfaceReferenceIsElevatorThenHover) {
  Rig rig;
  TestPeer peer(rig.port());
  start(peer);
  const auto there = dive(peer, 2.5);
  peer.send(reference_here(there, 0.0));
  auto up = peer.wait_for<imc::FollowRefState>([](const auto& s) { return s.reference.has_value(); });
  ASSERT_TRUE(up);
  EXPECT_EQ(imc::FollowRefState::kStateElevator, up->state);
  auto near_top = peer.wait_for<imc::EstimatedState>([](const auto& s) { return s.depth < 0.5; });
  ASSERT_TRUE(near_top);
  peer.send(reference_here(*near_top, 0.0));
  auto hover = peer.wait_for<imc::FollowRefState>([](const auto& s) { return s.reference.has_value(); });
  ASSERT_TRUE(hover);
  EXPECT_EQ(imc::FollowRefState::kStateHover, hover->state);
}

TEST(ImcVehicleServer, GpsFixOnlyAtTheSurfaceInOpenWater) {
  {
    Rig tank;
    TestPeer peer(tank.port());
    peer.announce();
    auto fix = peer.wait_for<imc::GpsFix>();
    ASSERT_TRUE(fix);
    EXPECT_EQ(0, fix->validity);
    EXPECT_EQ(0, fix->satellites);
  }
  Scenario s = Scenario::nominal();
  s.world.open_water = true;
  s.vehicle_x_m = 100.0;  // east
  s.vehicle_y_m = -50.0;  // south
  Rig sea(s);
  TestPeer peer(sea.port());
  peer.announce();
  auto fix = peer.wait_for<imc::GpsFix>();
  ASSERT_TRUE(fix);
  EXPECT_EQ(0x1FF, fix->validity);
  EXPECT_GT(fix->satellites, 0);
  EXPECT_NEAR(kImcOriginLatRad - 50.0 / kEarthRadiusM, fix->lat, 1e-9);
  EXPECT_GT(fix->lon, kImcOriginLonRad);
  auto est = peer.wait_for<imc::EstimatedState>();
  ASSERT_TRUE(est);
  EXPECT_EQ(kImcOriginLatRad, est->lat);
  EXPECT_NEAR(-50.0, est->x, 30.0);  // north, from the launch estimate (10 m per axis)
  EXPECT_NEAR(100.0, est->y, 30.0);  // east
  auto nu = peer.wait_for<imc::NavigationUncertainty>();
  ASSERT_TRUE(nu);
  EXPECT_GT(nu->x, 0.0f);  // open water: the estimate is uncertain
  EXPECT_EQ(nu->x, nu->y);
  // Below the surface, no fix.
  start(peer);
  dive(peer, 1.0);
  EXPECT_TRUE(peer.wait_for<imc::GpsFix>([](const auto& g) { return g.validity == 0 && g.satellites == 0; }));
}

// Without the socket: the coordinates the contract fixes.
TEST(ImcVehicle, ImcXIsNorthAndYIsEastOfTheOrigin) {
  Scenario s = Scenario::nominal();
  s.world.open_water = true;
  s.vehicle_x_m = 30.0;   // east
  s.vehicle_y_m = -20.0;  // south
  VehicleParams p = default_params();
  p.nav_initial_sd_m = 0.0;
  Simulation sim(p, s);
  ImcVehicle v(sim, ImcVehicleOptions{});
  v.step();
  const auto est = v.estimated_state();
  EXPECT_NEAR(-20.0, est.x, 0.05);
  EXPECT_NEAR(30.0, est.y, 0.05);
  const auto [lat, lon] = v.to_lat_lon(30.0, -20.0);
  EXPECT_NEAR(kImcOriginLatRad - 20.0 / kEarthRadiusM, lat, 1e-12);
  EXPECT_NEAR(kImcOriginLonRad + 30.0 / (kEarthRadiusM * std::cos(kImcOriginLatRad)), lon, 1e-12);
  const auto [x, y] = v.to_plan(lat, lon);
  EXPECT_NEAR(30.0, x, 1e-6);
  EXPECT_NEAR(-20.0, y, 1e-6);
  EXPECT_NEAR(1.7e9 + 0.1, v.timestamp(), 1e-6);
}

}  // namespace
}  // namespace strata::vehicle::imc_server_tests
