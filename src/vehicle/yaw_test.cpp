// Heading: the yaw model, the heading law, and set_heading() /
// heading_reached() on the Simulation.
#include "vehicle/yaw.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "vehicle/simulation.h"

namespace strata::vehicle {
namespace {

const VehicleParams kYawP = default_params();

Scenario facing(double heading_deg) {
  Scenario s = Scenario::nominal();
  s.vehicle_heading_deg = heading_deg;
  return s;
}

// A turn from `from` to `to` on a fresh simulation, stepped for limit_s:
// when heading_reached() first held, and how far the heading went past `to`.
struct Turn {
  double reached_s = -1.0;
  double overshoot_deg = 0.0;
  double max_rate_dps = 0.0;
  double max_error_deg = 0.0;  // |error| over the whole run
  bool stayed_reached = true;  // heading_reached() never lost once held
};

Turn turn(double from, double to, double limit_s = 40.0) {
  Simulation sim(kYawP, facing(from));
  EXPECT_TRUE(sim.start_network().ok());
  EXPECT_TRUE(sim.set_heading(to).ok());
  Turn t;
  const double direction = heading_error_deg(from, to) < 0.0 ? 1.0 : -1.0;  // +1: clockwise
  while (sim.time_s() < limit_s) {
    sim.step();
    const double e = heading_error_deg(sim.yaw().heading_deg, to);
    t.overshoot_deg = std::max(t.overshoot_deg, direction * e);
    t.max_rate_dps = std::max(t.max_rate_dps, std::abs(sim.yaw().rate_dps));
    t.max_error_deg = std::max(t.max_error_deg, std::abs(e));
    if (t.reached_s < 0.0 && sim.heading_reached()) t.reached_s = sim.time_s();
    if (t.reached_s >= 0.0 && !sim.heading_reached()) t.stayed_reached = false;
  }
  return t;
}

TEST(Heading, AnglesWrapToCompassDegrees) {
  EXPECT_EQ(0.0, wrap_heading_deg(360.0));
  EXPECT_EQ(350.0, wrap_heading_deg(-10.0));
  EXPECT_EQ(10.0, wrap_heading_deg(730.0));
  EXPECT_EQ(0.0, wrap_heading_deg(-1e-17));          // not 360
  EXPECT_EQ(-20.0, heading_error_deg(350.0, 10.0));  // turn 20 deg clockwise
  EXPECT_EQ(20.0, heading_error_deg(10.0, 350.0));
  EXPECT_EQ(-90.0, heading_error_deg(0.0, 90.0));
  EXPECT_EQ(-180.0, heading_error_deg(0.0, 180.0));
}

TEST(Heading, ANinetyDegreeTurnSettlesWithinFifteenSecondsWithoutOvershoot) {
  const Turn t = turn(0.0, 90.0);
  ASSERT_GE(t.reached_s, 0.0);
  EXPECT_LT(t.reached_s, 15.0);
  EXPECT_GT(t.reached_s, 5.0);  // the thrusters cannot do it much faster
  EXPECT_LT(t.overshoot_deg, 1.0);
  EXPECT_TRUE(t.stayed_reached);
  // The long part of the turn runs at the law's capped rate.
  EXPECT_NEAR(kYawP.hdg_max_rate_dps, t.max_rate_dps, 1.0);
}

TEST(Heading, TurnsTheShortWayRoundThroughNorth) {
  const Turn cw = turn(350.0, 10.0);
  ASSERT_GE(cw.reached_s, 0.0);
  EXPECT_LT(cw.reached_s, 10.0);
  EXPECT_LE(cw.max_error_deg, 20.0 + 1e-9);  // never the 340 degree way
  EXPECT_LT(cw.overshoot_deg, 1.0);
  const Turn ccw = turn(10.0, 350.0);
  ASSERT_GE(ccw.reached_s, 0.0);
  EXPECT_LE(ccw.max_error_deg, 20.0 + 1e-9);
  EXPECT_NEAR(cw.reached_s, ccw.reached_s, 1e-9);  // mirror images
}

TEST(Heading, AHalfTurnSettlesToo) {
  const Turn t = turn(0.0, 180.0);
  ASSERT_GE(t.reached_s, 0.0);
  EXPECT_LT(t.reached_s, 25.0);
  EXPECT_LT(t.overshoot_deg, 1.0);
}

TEST(Heading, YawDecaysByDragAloneWithTheThrustersOff) {
  // (I + I_a) dr/dt = -c r|r|: r(t) = r0 / (1 + c r0 t / (I + I_a)), and the
  // heading advances by (I + I_a)/c ln(1 + c r0 t / (I + I_a)).
  const double r0 = 20.0 * std::numbers::pi / 180.0;
  YawState s{100.0, 20.0, 0.0};
  const double h = kYawP.cycle_s / kYawP.substeps;
  for (int i = 0; i < 1000; ++i) advance_yaw(kYawP, 0.0, kYawP.max_yaw_moment_nm(), h, s);
  const double k = kYawP.yaw_drag_coeff * r0 * 10.0 / kYawP.total_yaw_inertia_kgm2();
  EXPECT_NEAR(20.0 / (1.0 + k), s.rate_dps, 0.02);
  const double turned = kYawP.total_yaw_inertia_kgm2() / kYawP.yaw_drag_coeff * std::log(1.0 + k);
  EXPECT_NEAR(100.0 + turned * 180.0 / std::numbers::pi, s.heading_deg, 0.2);
  EXPECT_EQ(0.0, s.moment_nm);
}

TEST(Heading, MomentFollowsTheCommandWithALagAndIsLimited) {
  YawState s;
  const double h = kYawP.cycle_s / kYawP.substeps;
  const int n = static_cast<int>(std::lround(kYawP.transverse_lag_s / h));
  for (int i = 0; i < n; ++i) advance_yaw(kYawP, 5.0, kYawP.max_yaw_moment_nm(), h, s);
  EXPECT_NEAR(5.0 * (1.0 - std::exp(-1.0)), s.moment_nm, 1e-9);
  for (int i = 0; i < 1000; ++i) advance_yaw(kYawP, 100.0, 2.0, h, s);
  EXPECT_NEAR(2.0, s.moment_nm, 1e-9);
  EXPECT_NEAR(10.8, kYawP.max_yaw_moment_nm(), 1e-12);  // 2 x 9 N x 0.6 m
  // From rest far away: the switching gain, the short way round.
  EXPECT_EQ(kYawP.hdg_gain_nm, heading_moment(kYawP, 0.0, 0.0, 170.0));
  EXPECT_EQ(-kYawP.hdg_gain_nm, heading_moment(kYawP, 0.0, 0.0, 190.0));
  // Arriving far too fast: full brake, clamped to what the thrusters give.
  EXPECT_EQ(-kYawP.max_yaw_moment_nm(), heading_moment(kYawP, 85.0, 30.0, 90.0));
}

TEST(Heading, IdleTransverseThrustersAreOffAndHeadingHoldNeedsTheNetwork) {
  Simulation sim(kYawP, facing(45.0));
  EXPECT_EQ(45.0, sim.telemetry().heading_deg);
  EXPECT_FALSE(sim.heading_reached());
  auto r = sim.set_heading(90.0);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ("network not started", r.error().message);
  ASSERT_TRUE(sim.start_network().ok());
  sim.advance(5.0);
  EXPECT_EQ(0.0, sim.telemetry().yaw_moment_cmd_nm);
  EXPECT_EQ(45.0, sim.yaw().heading_deg);
  EXPECT_FALSE(sim.telemetry().heading_setpoint_deg.has_value());
  EXPECT_FALSE(sim.set_heading(-1.0).ok());
  EXPECT_FALSE(sim.set_heading(360.5).ok());
  EXPECT_FALSE(sim.set_heading(std::nan("")).ok());
  ASSERT_TRUE(sim.set_heading(360.0).ok());
  EXPECT_EQ(0.0, sim.telemetry().heading_setpoint_deg);
  sim.advance(1.0);
  EXPECT_NE(0.0, sim.telemetry().yaw_moment_cmd_nm);
  ASSERT_TRUE(sim.shutdown_network().ok());
  sim.step();
  EXPECT_EQ(0.0, sim.telemetry().yaw_moment_cmd_nm);
  EXPECT_FALSE(sim.heading_reached());
}

TEST(Heading, AWatchdogTripDropsHeadingHoldUntilTheNetworkRestarts) {
  Simulation sim(kYawP, Scenario::nominal());
  ASSERT_TRUE(sim.start_network().ok());
  ASSERT_TRUE(sim.set_heading(90.0).ok());
  sim.watchdog_trip("test");
  EXPECT_FALSE(sim.telemetry().heading_setpoint_deg.has_value());
  EXPECT_FALSE(sim.set_heading(90.0).ok());
  ASSERT_TRUE(sim.start_network().ok());
  EXPECT_TRUE(sim.set_heading(90.0).ok());
}

TEST(Heading, TheDepthLawRunsUnchangedWhileTurning) {
  auto dive = [](bool turn) {
    Simulation sim(kYawP, Scenario::nominal(3));
    EXPECT_TRUE(sim.start_network().ok());
    EXPECT_TRUE(sim.start_depth_filter().ok());
    EXPECT_TRUE(sim.set_setpoint(1.5, 60.0).ok());
    EXPECT_TRUE(sim.submerge().ok());
    if (turn) {
      EXPECT_TRUE(sim.set_heading(135.0).ok());
    }
    std::vector<HeaveState> path;
    for (int i = 0; i < 300; ++i) {
      sim.step();
      path.push_back(sim.heave());
    }
    EXPECT_TRUE(sim.depth_reached());
    EXPECT_EQ(turn, sim.heading_reached());
    return path;
  };
  EXPECT_EQ(dive(false), dive(true));  // bit for bit
}

TEST(Heading, WeakThrustersTurnSlowerButStillArrive) {
  Scenario sc = Scenario::nominal();
  sc.faults.push_back(Fault{FaultKind::WeakThrusters, 0.0, 0.5, std::nullopt});
  Simulation sim(kYawP, sc);
  ASSERT_TRUE(sim.start_network().ok());
  ASSERT_TRUE(sim.set_heading(90.0).ok());
  sim.advance(10.0);
  EXPECT_FALSE(sim.heading_reached());
  EXPECT_LE(std::abs(sim.telemetry().yaw_moment_nm), 0.5 * kYawP.max_yaw_moment_nm() + 1e-9);
  sim.advance(20.0);
  EXPECT_TRUE(sim.heading_reached());
}

}  // namespace
}  // namespace strata::vehicle
