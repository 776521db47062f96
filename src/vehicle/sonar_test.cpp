// The scanning sonar: ping geometry, the sweep, timing and the buffer, the
// target detector, determinism; and the sonar on the Simulation.
#include "vehicle/sonar.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "vehicle/simulation.h"

namespace strata::vehicle {
namespace {

const VehicleParams kSonarP = default_params();
constexpr double kBin_m = 10.0 / 200;  // range_m / bins

int strongest_bin(const protocol::SonarPing& ping) {
  return static_cast<int>(std::max_element(ping.bins.begin(), ping.bins.end()) - ping.bins.begin());
}

int strongest_in(const protocol::SonarPing& ping, int lo, int hi) {
  return *std::max_element(ping.bins.begin() + lo, ping.bins.begin() + hi + 1);
}

Scenario placed(double x_m, double y_m, double heading_deg, std::optional<Target> target, std::uint64_t seed = 1) {
  Scenario s = Scenario::nominal(seed);
  s.vehicle_x_m = x_m;
  s.vehicle_y_m = y_m;
  s.vehicle_heading_deg = heading_deg;
  s.target = target;
  return s;
}

// A simulation with the network up and the sonar on.
Simulation pinging(const Scenario& s, VehicleParams p = kSonarP) {
  Simulation sim(p, s);
  EXPECT_TRUE(sim.start_network().ok());
  EXPECT_TRUE(sim.start_sonar().ok());
  return sim;
}

TEST(SonarGeometry, RaysMeetTheWallsAndTheCylinder) {
  // From (6, 3) in the 12 x 8 m tank.
  EXPECT_NEAR(5.0, wall_hit(kSonarP, 6.0, 3.0, 0.0).range_m, 1e-12);
  EXPECT_NEAR(6.0, wall_hit(kSonarP, 6.0, 3.0, 90.0).range_m, 1e-12);
  EXPECT_NEAR(3.0, wall_hit(kSonarP, 6.0, 3.0, 180.0).range_m, 1e-12);
  EXPECT_NEAR(6.0, wall_hit(kSonarP, 6.0, 3.0, 270.0).range_m, 1e-12);
  const RayHit oblique = wall_hit(kSonarP, 6.0, 3.0, 30.0);
  EXPECT_NEAR(5.0 / std::cos(std::numbers::pi / 6), oblique.range_m, 1e-12);
  EXPECT_NEAR(std::cos(std::numbers::pi / 6), oblique.cos_incidence, 1e-12);

  const Target t{6.0, 6.0, 0.5};
  const auto ahead = cylinder_hit(t, 6.0, 3.0, 0.0);
  ASSERT_TRUE(ahead);
  EXPECT_NEAR(2.5, ahead->range_m, 1e-12);
  EXPECT_NEAR(1.0, ahead->cos_incidence, 1e-12);
  EXPECT_FALSE(cylinder_hit(t, 6.0, 3.0, 180.0));  // behind
  EXPECT_FALSE(cylinder_hit(t, 6.0, 3.0, 15.0));   // beside: asin(0.5 / 3) = 9.6 deg
  EXPECT_TRUE(cylinder_hit(t, 6.0, 3.0, 9.0));
  EXPECT_FALSE(cylinder_hit(t, 6.0, 5.8, 0.0));  // inside
}

TEST(SonarGeometry, TheVehicleHoversWhereTheScenarioSaysOrAtTheCentre) {
  EXPECT_EQ(6.0, Simulation(kSonarP, Scenario::nominal()).pose().x_m);
  EXPECT_EQ(4.0, Simulation(kSonarP, Scenario::nominal()).pose().y_m);
  Simulation sim(kSonarP, placed(2.0, 7.0, 300.0, std::nullopt));
  EXPECT_EQ(2.0, sim.pose().x_m);
  EXPECT_EQ(7.0, sim.pose().y_m);
  EXPECT_EQ(300.0, sim.pose().heading_deg);
  EXPECT_TRUE(sim.events().empty());
  // Outside the 12 x 8 m tank: moved to its edge, and said so.
  Simulation out(kSonarP, placed(20.0, 3.0, 0.0, std::nullopt));
  EXPECT_EQ(12.0, out.pose().x_m);
  ASSERT_EQ(1u, out.events().size());
  EXPECT_EQ("scenario: vehicle at (20, 3) m is outside the 12 x 8 m tank: placed at (12, 3) m", out.events()[0].text);
}

TEST(SonarPings, TheWallAheadIsStrongestInItsBin) {
  // y = 3.93: the wall y = 8 m is 4.07 m ahead, bin 81.
  Simulation sim = pinging(placed(6.0, 3.93, 0.0, std::nullopt));
  sim.step();
  const auto pings = sim.take_pings();
  ASSERT_FALSE(pings.empty());
  const protocol::SonarPing& p = pings[0];
  EXPECT_EQ(0u, p.seq);
  EXPECT_EQ(0.0f, p.bearing_deg);
  EXPECT_EQ(0.0f, p.heading_deg);
  EXPECT_EQ(6.0f, p.x_m);
  EXPECT_EQ(3.93f, p.y_m);
  EXPECT_EQ(10.0f, p.range_m);
  ASSERT_EQ(200u, p.bins.size());
  EXPECT_NEAR(4.07 / kBin_m, strongest_bin(p), 1.0);
  EXPECT_GT(p.bins[81], 150);               // 180 counts head on
  EXPECT_LT(strongest_in(p, 0, 75), 90);    // water: noise only
  EXPECT_LT(strongest_in(p, 87, 199), 90);  // beyond the wall: nothing
}

TEST(SonarPings, TurningTheVehicleMovesTheWall) {
  // From (5.93, 3.93): east wall 6.07 m, west 5.93 m, south 3.93 m.
  const std::pair<double, double> cases[] = {{90.0, 6.07}, {270.0, 5.93}, {180.0, 3.93}};
  for (const auto& [heading, range] : cases) {
    Simulation sim = pinging(placed(5.93, 3.93, heading, std::nullopt));
    sim.step();
    const auto pings = sim.take_pings();
    ASSERT_FALSE(pings.empty());
    EXPECT_EQ(static_cast<float>(heading), pings[0].heading_deg);
    EXPECT_NEAR(range / kBin_m, strongest_bin(pings[0]), 1.0) << heading;
  }
}

TEST(SonarPings, ATargetOnTheBeamEchoesAndShadowsTheWall) {
  // From (6, 2) heading 0: a cylinder of radius 0.3 m at (6, 6) has its near
  // side 3.7 m ahead (bin 74); the wall 6 m ahead (bin 120) is behind it.
  Sonar with(kSonarP, 1, Target{6.0, 6.0, 0.3});
  const auto p = with.make_ping(0.0, 0.0, Pose{6.0, 2.0, 0.0});
  EXPECT_NEAR(3.7 / kBin_m, strongest_bin(p), 1.0);
  EXPECT_GT(strongest_in(p, 73, 75), 150);
  EXPECT_LT(strongest_in(p, 110, 130), 60);  // shadow
  EXPECT_TRUE(with.shows_target(p));

  Sonar without(kSonarP, 1, std::nullopt);
  const auto q = without.make_ping(0.0, 0.0, Pose{6.0, 2.0, 0.0});
  EXPECT_NEAR(6.0 / kBin_m, strongest_bin(q), 1.0);
  EXPECT_GT(strongest_in(q, 119, 121), 150);
  EXPECT_LT(strongest_in(q, 60, 90), 90);
  EXPECT_FALSE(without.shows_target(q));

  // Off the beam the target is not seen and the wall is back.
  const auto r = with.make_ping(0.0, 10.8, Pose{6.0, 2.0, 0.0});
  EXPECT_LT(strongest_in(r, 60, 90), 90);
  EXPECT_FALSE(with.shows_target(r));
}

TEST(SonarScan, SweepsBackAndForthOverTheSectorOneStepPerPing) {
  Simulation sim = pinging(placed(6.0, 4.0, 0.0, std::nullopt));
  sim.advance(12.0);
  const auto pings = sim.take_pings();
  ASSERT_GE(pings.size(), 200u);
  // 60 / 1.8 = 33.3: the ends are 33 steps out, +-59.4 deg.
  std::vector<double> expected;
  for (int k = 0; k <= 33; ++k) expected.push_back(1.8 * k);
  for (int k = 32; k >= -33; --k) expected.push_back(1.8 * k);
  for (int k = -32; k <= 33; ++k) expected.push_back(1.8 * k);
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_NEAR(expected[i], pings[i].bearing_deg, 1e-4) << i;
  }
  Sonar s(kSonarP, 1, std::nullopt);
  EXPECT_EQ(67, s.sweep_pings());
}

TEST(SonarScan, PingsComeEveryFiftyMillisecondsWithoutGapsUntilStopped) {
  Simulation sim = pinging(placed(6.0, 4.0, 0.0, std::nullopt));
  std::vector<protocol::SonarPing> all;
  for (int i = 0; i < 10; ++i) {
    sim.advance(1.0);
    for (auto& p : sim.take_pings()) all.push_back(std::move(p));
  }
  ASSERT_EQ(200u, all.size());  // 20 pings a second
  for (std::size_t i = 0; i < all.size(); ++i) {
    EXPECT_EQ(i, all[i].seq);
    EXPECT_NEAR(0.01 + 0.05 * static_cast<double>(i), all[i].time_s, 1e-9) << i;
  }
  ASSERT_TRUE(sim.stop_sonar().ok());
  EXPECT_FALSE(sim.sonar_on());
  sim.advance(2.0);
  EXPECT_TRUE(sim.take_pings().empty());
  // Restarted, the count goes on.
  ASSERT_TRUE(sim.start_sonar().ok());
  sim.step();
  const auto more = sim.take_pings();
  ASSERT_FALSE(more.empty());
  EXPECT_EQ(200u, more[0].seq);
  EXPECT_EQ(0u, sim.pings_dropped());
}

TEST(SonarScan, AFullBufferDropsTheOldestAndCountsThem) {
  VehicleParams p = kSonarP;
  p.sonar_buffer_pings = 10;
  Simulation sim = pinging(placed(6.0, 4.0, 0.0, std::nullopt), p);
  sim.advance(2.0);
  const auto pings = sim.take_pings();
  ASSERT_EQ(10u, pings.size());
  EXPECT_EQ(30u, sim.pings_dropped());
  EXPECT_EQ(30u, pings.front().seq);
  EXPECT_EQ(39u, pings.back().seq);
}

TEST(SonarScan, CommandsNeedTheNetworkAndShutdownStopsIt) {
  Simulation sim(kSonarP, Scenario::nominal());
  EXPECT_FALSE(sim.start_sonar().ok());
  EXPECT_FALSE(sim.stop_sonar().ok());
  sim.advance(1.0);
  EXPECT_TRUE(sim.take_pings().empty());
  ASSERT_TRUE(sim.start_network().ok());
  ASSERT_TRUE(sim.start_sonar().ok());
  ASSERT_TRUE(sim.start_sonar().ok());  // idempotent
  EXPECT_TRUE(sim.telemetry().sonar_on);
  ASSERT_TRUE(sim.shutdown_network().ok());
  EXPECT_FALSE(sim.sonar_on());
}

TEST(SonarDetector, FindsATargetAheadWithinASweep) {
  Simulation sim = pinging(placed(6.0, 2.0, 0.0, Target{6.0, 6.0, 0.3}));
  EXPECT_FALSE(sim.target_detected());
  sim.advance(3.4);  // 67 pings: one sweep
  EXPECT_TRUE(sim.target_detected());
  ASSERT_TRUE(sim.stop_sonar().ok());
  EXPECT_FALSE(sim.target_detected());  // false while off
}

TEST(SonarDetector, FindsATargetOffTheBowAndLosesItWhenTurnedAway) {
  // 4 m away at 40 deg to starboard of north.
  const double a = 40.0 * std::numbers::pi / 180.0;
  const Target t{6.0 + 4.0 * std::sin(a), 2.0 + 4.0 * std::cos(a), 0.3};
  Simulation ahead = pinging(placed(6.0, 2.0, 0.0, t));
  ahead.advance(3.4);
  EXPECT_TRUE(ahead.target_detected());
  // Its echo (near side 3.7 m, bin 74) is in the pings to starboard.
  int echoes = 0;
  for (const auto& p : ahead.take_pings()) {
    if (strongest_in(p, 70, 78) < 120) continue;
    ++echoes;
    EXPECT_NEAR(40.0, p.bearing_deg, 4.0);
  }
  EXPECT_GE(echoes, 2);
  Simulation away = pinging(placed(6.0, 2.0, 180.0, t));  // outside the +-60 deg sector
  for (int i = 0; i < 600; ++i) {
    away.step();
    ASSERT_FALSE(away.target_detected()) << away.time_s();
  }
}

// A bearing near the end of the sector is passed twice in quick succession,
// then not for most of a scan period: once seen, the target stays detected
// for as long as the vehicle keeps looking (a window of one way flickered).
TEST(SonarDetector, ATargetNearTheEndOfTheSectorStaysDetected) {
  const double a = 35.0 * std::numbers::pi / 180.0;
  const Target t{6.0 + 3.6 * std::sin(a), 2.0 + 3.6 * std::cos(a), 0.3};
  Simulation sim = pinging(placed(6.0, 2.0, 0.0, t));
  sim.advance(6.7);  // a scan period, there and back
  for (int i = 0; i < 300; ++i) {
    sim.step();
    ASSERT_TRUE(sim.target_detected()) << sim.time_s();
  }
}

TEST(SonarDetector, NothingIsDetectedInAnEmptyTank) {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    Simulation sim = pinging(placed(6.0, 2.0, 0.0, std::nullopt, seed));
    ASSERT_TRUE(sim.set_heading(90.0).ok());  // walls at every incidence
    for (int i = 0; i < 600; ++i) {
      sim.step();
      ASSERT_FALSE(sim.target_detected()) << "seed " << seed << " at " << sim.time_s();
    }
  }
}

// Open water has no walls: a vehicle far outside the tank's plan (where the
// tank's geometry put a wall at 0 m) hears only noise, and a target ahead of
// it within range is echoed and detected.
TEST(SonarOpenWater, NoWallsOnlyNoiseAndTheTarget) {
  Sonar empty(kSonarP, 1, std::nullopt, /*tank_walls=*/false);
  const auto q = empty.make_ping(0.0, 0.0, Pose{150.0, 40.0, 90.0});
  EXPECT_LT(strongest_in(q, 0, 199), 90);  // noise only, no wall at 0 m
  EXPECT_FALSE(empty.shows_target(q));

  Sonar with(kSonarP, 1, Target{154.0, 40.0, 0.3}, /*tank_walls=*/false);
  const auto p = with.make_ping(0.0, 0.0, Pose{150.0, 40.0, 90.0});
  EXPECT_NEAR(3.7 / kBin_m, strongest_bin(p), 1.0);
  EXPECT_TRUE(with.shows_target(p));

  Scenario s = placed(150.0, 40.0, 90.0, std::nullopt);
  s.world.open_water = true;
  Simulation sim = pinging(s);
  for (int i = 0; i < 100; ++i) {
    sim.step();
    ASSERT_FALSE(sim.target_detected()) << sim.time_s();
  }
  const auto pings = sim.take_pings();
  ASSERT_FALSE(pings.empty());
  for (const auto& ping : pings) ASSERT_LT(strongest_in(ping, 0, 199), 90) << ping.seq;
}

TEST(SonarDeterminism, SameScenarioSamePingsAndTrajectoryBitForBit) {
  auto run = [](std::uint64_t seed) {
    Simulation sim = pinging(placed(4.0, 3.0, 20.0, Target{7.0, 6.0, 0.25}, seed));
    EXPECT_TRUE(sim.set_heading(200.0).ok());
    std::vector<protocol::SonarPing> pings;
    std::vector<Telemetry> path;
    for (int i = 0; i < 300; ++i) {
      sim.step();
      path.push_back(sim.telemetry());
      for (auto& p : sim.take_pings()) pings.push_back(std::move(p));
    }
    return std::pair{pings, path};
  };
  const auto a = run(7);
  const auto b = run(7);
  ASSERT_EQ(600u, a.first.size());
  EXPECT_TRUE(a.first == b.first);
  EXPECT_TRUE(a.second == b.second);
  const auto c = run(8);
  EXPECT_FALSE(a.first == c.first);  // other noise
}

TEST(SonarDeterminism, TheSonarLeavesTheDepthCellsNoiseAlone) {
  auto readings = [](bool sonar) {
    Simulation sim(kSonarP, Scenario::nominal(5));
    EXPECT_TRUE(sim.start_network().ok());
    if (sonar) {
      EXPECT_TRUE(sim.start_sonar().ok());
    }
    std::vector<std::optional<double>> out;
    for (int i = 0; i < 100; ++i) {
      sim.step();
      out.push_back(sim.telemetry().measured_depth_m);
    }
    return out;
  };
  EXPECT_EQ(readings(false), readings(true));
}

}  // namespace
}  // namespace strata::vehicle
