// Sway: the transverse thrusters pushing the same way (sway.h), set_sway,
// the heading law's priority, weak thrusters, and dead reckoning with the
// modelled sway.
#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "vehicle/open_water_test_support.h"
#include "vehicle/simulation.h"

namespace strata::vehicle {
namespace {

using test_support::open_water;
using test_support::started;

TEST(Sway, TheParametersGiveATopSwaySpeedFromBothThrusters) {
  const VehicleParams p = default_params();
  EXPECT_DOUBLE_EQ(18.0, p.max_sway_force_n());  // 2 x 9 N
  EXPECT_NEAR(std::sqrt(18.0 / 220.0), p.top_sway_speed_mps(), 1e-12);
  EXPECT_DOUBLE_EQ(350.0, p.total_sway_mass_kg());
  // What the heading law's moment leaves, at health h: 2 T h - |M| / L.
  EXPECT_NEAR(18.0 - 6.0 / 0.6, sway_force_limit_n(p, -6.0, 1.0), 1e-12);
  EXPECT_NEAR(9.0 - 3.0 / 0.6, sway_force_limit_n(p, 3.0, 0.5), 1e-12);
  EXPECT_EQ(0.0, sway_force_limit_n(p, p.max_yaw_moment_nm(), 1.0));  // all of it to yaw
}

TEST(Sway, AStepToStarboardMovesTheVehicleSidewaysWithItsHeadingHeld) {
  Simulation sim = started(open_water());  // heading 0: starboard is east (+x)
  ASSERT_TRUE(sim.set_heading(0.0).ok());
  ASSERT_TRUE(sim.set_sway(0.2).ok());
  double t63 = -1.0, peak = 0.0, worst_heading = 0.0;
  for (int i = 0; i < 600; ++i) {
    sim.step();
    if (t63 < 0.0 && sim.sway().speed_mps >= 0.63 * 0.2) t63 = sim.time_s();
    peak = std::max(peak, sim.sway().speed_mps);
    worst_heading = std::max(worst_heading, std::abs(heading_error_deg(sim.yaw().heading_deg, 0.0)));
  }
  // From rest v = v_d tanh(t c v_d / (m + m_a)): 63% at 0.741 * 350 / (220 *
  // 0.2) = 5.9 s, plus about the thrusters' lag, 0.3 s.
  EXPECT_NEAR(6.2, t63, 0.3);
  EXPECT_NEAR(0.2, sim.sway().speed_mps, 0.002);  // feed-forward: the asked speed
  EXPECT_LE(peak, 0.2 + 1e-6);                    // no overshoot
  EXPECT_LT(worst_heading, 0.5);
  EXPECT_EQ(0.0, sim.surge().speed_mps);
  // 60 s at up to 0.2 m/s, less the start: east, not north.
  EXPECT_GT(sim.pose().x_m, 9.5);
  EXPECT_LT(sim.pose().x_m, 12.0);
  EXPECT_NEAR(0.0, sim.pose().y_m, 1e-9);
}

TEST(Sway, PortIsNegativeAndTurnsWithTheHeading) {
  Simulation sim = started(open_water("[vehicle]\nheading_deg = 90.0\n"));  // bow east: port is north
  ASSERT_TRUE(sim.set_heading(90.0).ok());
  ASSERT_TRUE(sim.set_sway(-0.15).ok());
  sim.advance(60.0);
  EXPECT_NEAR(-0.15, sim.sway().speed_mps, 0.002);
  EXPECT_GT(sim.pose().y_m, 6.0);
  EXPECT_NEAR(0.0, sim.pose().x_m, 1e-6);
}

TEST(Sway, TheHeadingLawKeepsPriorityInATurn) {
  Simulation plain = started(open_water());
  Simulation swaying = started(open_water());
  Simulation straight = started(open_water());
  ASSERT_TRUE(plain.set_heading(90.0).ok());
  ASSERT_TRUE(swaying.set_heading(90.0).ok());
  ASSERT_TRUE(swaying.set_sway(0.2).ok());
  ASSERT_TRUE(straight.set_heading(0.0).ok());  // no turn: all of the thrust to sway
  ASSERT_TRUE(straight.set_sway(0.2).ok());
  const VehicleParams& p = swaying.params();
  EXPECT_DOUBLE_EQ(8.8, sway_force_n(p, 0.2));  // asked: 220 x 0.2^2
  double least_cmd = 1e9;
  for (int i = 0; i < 150; ++i) {
    plain.step();
    swaying.step();
    straight.step();
    // The turn is exactly the turn without sway: yaw gets what it asks for.
    ASSERT_EQ(plain.yaw(), swaying.yaw()) << "at " << swaying.time_s() << " s";
    // Neither thruster beyond its limit: |M| / L + |F| <= 2 T_max.
    EXPECT_LE(std::abs(swaying.yaw().moment_nm) / p.transverse_lever_m + std::abs(swaying.sway().force_n),
              p.max_sway_force_n() + 1e-9);
    least_cmd = std::min(least_cmd, swaying.sway_force_cmd_n());
    EXPECT_EQ(8.8, straight.sway_force_cmd_n());
    if (i == 19) {  // 2 s into the turn: the sway is well behind
      EXPECT_LT(swaying.sway().speed_mps, 0.5 * straight.sway().speed_mps);
    }
  }
  // Starting and ending the turn the heading law asks for at least its
  // switching gain, 10 N m (up to the full 10.8): 16.7 N or more of the 18 N
  // go to yaw, at most 1.3 N are left for sway, at times none.
  EXPECT_LE(least_cmd, p.max_sway_force_n() - p.hdg_gain_nm / p.transverse_lever_m);
  EXPECT_GE(least_cmd, 0.0);
  EXPECT_LT(swaying.sway().speed_mps, straight.sway().speed_mps - 0.01);
  // Once on the new heading the sway law gets its force back.
  swaying.advance(60.0);
  EXPECT_EQ(8.8, swaying.sway_force_cmd_n());
  EXPECT_NEAR(0.2, swaying.sway().speed_mps, 0.003);
}

TEST(Sway, WeakThrustersLimitIt) {
  Simulation sim = started(open_water(
      "[[fault]]\nkind = \"weak_thrusters\"\nat_s = 0.0\nhealth = 0.25\n[[fault]]\nkind = \"no_gps\"\nat_s = 0.0\n"));
  ASSERT_TRUE(sim.set_heading(0.0).ok());
  ASSERT_TRUE(sim.set_sway(0.2).ok());
  const double x0 = sim.navigator().x_m();
  sim.advance(90.0);
  // 2 x 9 N x 0.25 = 4.5 N: sqrt(4.5 / 220) = 0.143 m/s, not 0.2.
  EXPECT_NEAR(std::sqrt(4.5 / 220.0), sim.sway().speed_mps, 0.002);
  // The vehicle's own model assumes nominal thrusters: dead reckoning runs
  // ahead of the truth (the estimate's error grows with the shortfall).
  EXPECT_NEAR(0.2, sim.sway_model_mps(), 0.002);
  const double dr = sim.navigator().x_m() - x0;
  EXPECT_GT(dr - sim.pose().x_m, 3.0);
}

TEST(Sway, DeadReckoningFollowsTheModelledSway) {
  Simulation sim = started(open_water("[[fault]]\nkind = \"no_gps\"\nat_s = 0.0\n"));
  ASSERT_TRUE(sim.set_heading(0.0).ok());
  const double x0 = sim.navigator().x_m(), y0 = sim.navigator().y_m();
  ASSERT_TRUE(sim.set_sway(0.2).ok());
  sim.advance(60.0);
  // Nominal thrusters: the model is the truth; the estimate moved as the
  // vehicle did, to within dead reckoning's once-a-cycle integration (a
  // cycle's speed change while accelerating, about 1 cm).
  EXPECT_EQ(sim.sway().speed_mps, sim.sway_model_mps());
  EXPECT_NEAR(sim.pose().x_m, sim.navigator().x_m() - x0, 0.02);
  EXPECT_NEAR(sim.pose().y_m, sim.navigator().y_m() - y0, 1e-9);
  EXPECT_GT(sim.pose().x_m, 9.5);
}

TEST(Sway, OutOfRangeIsRefusedAndStopDropsIt) {
  Simulation sim = started(open_water());
  const double top = sim.params().top_sway_speed_mps();
  EXPECT_FALSE(sim.set_sway(top + 0.01).ok());
  EXPECT_FALSE(sim.set_sway(-top - 0.01).ok());
  EXPECT_FALSE(sim.set_sway(std::nan("")).ok());
  EXPECT_FALSE(sim.set_sway(INFINITY).ok());
  EXPECT_FALSE(sim.sway_setpoint_mps().has_value());
  ASSERT_TRUE(sim.set_sway(-top).ok());
  ASSERT_TRUE(sim.set_speed(0.5).ok());
  sim.advance(20.0);
  EXPECT_LT(sim.sway().speed_mps, -0.2);
  ASSERT_TRUE(sim.stop().ok());
  EXPECT_FALSE(sim.sway_setpoint_mps().has_value());
  sim.advance(1.0);
  EXPECT_EQ(0.0, sim.sway_force_cmd_n());
  sim.advance(120.0);
  EXPECT_GT(sim.sway().speed_mps, -0.02);  // coasting to rest, as surge does
  EXPECT_LT(std::abs(sim.sway().force_n), 1e-9);
  Simulation down = started(open_water());
  ASSERT_TRUE(down.shutdown_network().ok());
  EXPECT_FALSE(down.set_sway(0.1).ok());  // the network first
  Simulation tripped = started(open_water());
  ASSERT_TRUE(tripped.set_sway(0.1).ok());
  tripped.watchdog_trip("test");
  EXPECT_FALSE(tripped.sway_setpoint_mps().has_value());
  EXPECT_FALSE(tripped.set_sway(0.1).ok());
}

TEST(Sway, NeverAskedItStaysExactlyAtRest) {
  Simulation sim = started(open_water());
  ASSERT_TRUE(sim.set_speed(0.8).ok());
  ASSERT_TRUE(sim.goto_xy(100.0, 100.0).ok());
  for (int i = 0; i < 600; ++i) {
    sim.step();
    ASSERT_EQ(SwayState{}, sim.sway());
    ASSERT_EQ(0.0, sim.sway_model_mps());
  }
}

}  // namespace
}  // namespace strata::vehicle
