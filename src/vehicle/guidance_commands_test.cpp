// Issue 37's vehicle: the rows of a lawnmower, loiter, hold_position,
// set_timer, gps_available, what the vehicle does after a waypoint, after
// stop and after set_speed, and which faults system_problem reports.
#include <cmath>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "protocol/rows.h"
#include "vehicle/open_water_test_support.h"
#include "vehicle/simulation.h"

namespace strata::vehicle {
namespace {

using protocol::Row;
using protocol::RowPattern;
using test_support::open_water;
using test_support::started;

double distance_to(const Simulation& sim, double x_m, double y_m) {
  return std::hypot(sim.pose().x_m - x_m, sim.pose().y_m - y_m);
}

// Steps until pred() holds, at most limit_s; the time it took, or -1.
template <typename Pred>
double steps_until(Simulation& sim, Pred pred, double limit_s) {
  const double t0 = sim.time_s();
  while (sim.time_s() - t0 < limit_s - 1e-9) {
    sim.step();
    if (pred()) return sim.time_s() - t0;
  }
  return -1.0;
}

RowPattern pattern(double heading, double spacing, double count) {
  std::string why;
  auto p = protocol::make_row_pattern(10.0, 20.0, heading, 100.0, spacing, count, &why);
  EXPECT_TRUE(p.has_value()) << why;
  return p.value_or(RowPattern{});
}

void expect_row(const Row& want, const Row& got) {
  EXPECT_NEAR(want.x0_m, got.x0_m, 1e-9);
  EXPECT_NEAR(want.y0_m, got.y0_m, 1e-9);
  EXPECT_NEAR(want.x1_m, got.x1_m, 1e-9);
  EXPECT_NEAR(want.y1_m, got.y1_m, 1e-9);
}

// ---- rows geometry (protocol/rows.h) --------------------------------------------

TEST(Rows, EastwardRowsStepToStarboardAndRunBackAndForth) {
  const RowPattern p = pattern(90.0, 20.0, 3);  // east; starboard of east is south
  expect_row({10.0, 20.0, 110.0, 20.0}, protocol::row_of(p, 0));
  expect_row({110.0, 0.0, 10.0, 0.0}, protocol::row_of(p, 1));  // back, 20 m south
  expect_row({10.0, -20.0, 110.0, -20.0}, protocol::row_of(p, 2));
}

TEST(Rows, NegativeSpacingStepsToPort) {
  const RowPattern p = pattern(0.0, -15.0, 2);  // north; port of north is west
  expect_row({10.0, 20.0, 10.0, 120.0}, protocol::row_of(p, 0));
  expect_row({-5.0, 120.0, -5.0, 20.0}, protocol::row_of(p, 1));
}

TEST(Rows, AnObliqueHeadingKeepsRowsParallelAndSpaced) {
  const RowPattern p = pattern(30.0, 25.0, 4);
  for (int i = 1; i < 4; ++i) {
    const Row a = protocol::row_of(p, i - 1);
    const Row b = protocol::row_of(p, i);
    // Each row starts where the one before it ended, one spacing across.
    EXPECT_NEAR(25.0, std::hypot(b.x0_m - a.x1_m, b.y0_m - a.y1_m), 1e-9);
    EXPECT_NEAR(100.0, std::hypot(b.x1_m - b.x0_m, b.y1_m - b.y0_m), 1e-9);
  }
}

TEST(Rows, BadPatternsAreRefusedWithAReason) {
  std::string why;
  EXPECT_FALSE(protocol::make_row_pattern(0, 0, 90, 100, 20, 0, &why));
  EXPECT_EQ("row count 0 is not a whole number from 1 to 1000", why);
  EXPECT_FALSE(protocol::make_row_pattern(0, 0, 90, 100, 20, 2.5, &why));
  EXPECT_FALSE(protocol::make_row_pattern(0, 0, 90, 100, 20, 1001, &why));
  EXPECT_FALSE(protocol::make_row_pattern(0, 0, 90, 0, 20, 2, &why));
  EXPECT_EQ("row length 0 m outside (0, 20000] m", why);
  EXPECT_FALSE(protocol::make_row_pattern(0, 0, 361, 100, 20, 2, &why));
  EXPECT_FALSE(protocol::make_row_pattern(0, NAN, 90, 100, 20, 2, &why));
  EXPECT_TRUE(protocol::make_row_pattern(0, 0, 360, 100, -20, 1000, &why));
}

// ---- rows on the vehicle ---------------------------------------------------------

TEST(RowsOnTheVehicle, NextRowTracksEachRowAndRowsDoneSaysWhenNoneIsLeft) {
  Simulation sim = started(open_water());
  EXPECT_FALSE(sim.rows_done());  // no pattern: next_row is refused, never silently done
  EXPECT_FALSE(sim.next_row().ok());
  ASSERT_TRUE(sim.start_rows(0.0, 0.0, 90.0, 60.0, 15.0, 2).ok());
  EXPECT_EQ(GuidanceMode::None, sim.guidance().mode);  // no motion by itself
  EXPECT_FALSE(sim.rows_done());
  ASSERT_TRUE(sim.next_row().ok());
  EXPECT_EQ(GuidanceMode::Track, sim.guidance().mode);
  EXPECT_FALSE(sim.rows_done());
  ASSERT_GT(steps_until(
                sim, [&] { return sim.waypoint_reached(); }, 200.0),
            0.0);
  EXPECT_NEAR(60.0, sim.navigator().x_m(), 4.0);
  ASSERT_TRUE(sim.next_row().ok());  // back west, 15 m south
  EXPECT_TRUE(sim.rows_done());
  EXPECT_FALSE(sim.waypoint_reached());
  ASSERT_GT(steps_until(
                sim, [&] { return sim.waypoint_reached(); }, 300.0),
            0.0);
  EXPECT_NEAR(0.0, sim.navigator().x_m(), 4.0);
  EXPECT_NEAR(-15.0, sim.navigator().y_m(), 3.0);
  auto none = sim.next_row();
  ASSERT_FALSE(none.ok());
  EXPECT_EQ("no row left: all 2 rows started", none.error().message);
  // A new pattern resets the cursor.
  ASSERT_TRUE(sim.start_rows(0.0, -15.0, 0.0, 30.0, 10.0, 1).ok());
  EXPECT_FALSE(sim.rows_done());
  EXPECT_FALSE(sim.start_rows(0.0, 0.0, 90.0, 2.0, 10.0, 1).ok());  // shorter than the waypoint radius
}

// ---- after a waypoint, after stop, set_speed ----------------------------------------

TEST(AfterAWaypoint, TheVehicleHoldsTheWaypointInACurrent) {
  Simulation sim = started(open_water("current_y_mps = 0.1\n"));
  sim.advance(120.0);  // fixes at the surface learn the current
  ASSERT_TRUE(sim.goto_xy(100.0, 0.0).ok());
  ASSERT_GT(steps_until(
                sim, [&] { return sim.waypoint_reached(); }, 400.0),
            0.0);
  EXPECT_EQ(GuidanceMode::Hold, sim.guidance().mode);
  double worst = 0.0;
  for (int i = 0; i < 6000; ++i) {  // ten minutes
    sim.step();
    worst = std::max(worst, distance_to(sim, 100.0, 0.0));
    ASSERT_TRUE(sim.waypoint_reached());  // latched
  }
  // Before: it ran on east at 0.8 m/s, 480 m off after ten minutes.
  EXPECT_LT(worst, 12.0);
  EXPECT_LT(distance_to(sim, 100.0, 0.0), 6.0);
}

TEST(AfterAWaypoint, AtrackLineEndsAtItsEndPoint) {
  Simulation sim = started(open_water());
  ASSERT_TRUE(sim.track(0.0, 0.0, 0.0, 80.0).ok());
  ASSERT_GT(steps_until(
                sim, [&] { return sim.waypoint_reached(); }, 300.0),
            0.0);
  sim.advance(300.0);
  EXPECT_LT(distance_to(sim, 0.0, 80.0), 6.0);
}

TEST(SetSpeed, AtTheSurfaceItMovesNothingAndAGuidanceCommandUsesIt) {
  Simulation sim = started(open_water());
  ASSERT_TRUE(sim.set_speed(0.5).ok());
  sim.advance(60.0);
  EXPECT_DOUBLE_EQ(0.0, sim.surge().speed_mps);
  EXPECT_DOUBLE_EQ(0.0, sim.pose().x_m);
  EXPECT_DOUBLE_EQ(0.0, sim.pose().y_m);
  EXPECT_FALSE(sim.telemetry().speed_setpoint_mps.has_value());
  ASSERT_TRUE(sim.goto_xy(0.0, 500.0).ok());
  sim.advance(60.0);
  EXPECT_NEAR(0.5, sim.surge().speed_mps, 0.01);
  // A guidance running takes a new speed at once.
  ASSERT_TRUE(sim.set_speed(0.7).ok());
  EXPECT_EQ(0.7, sim.telemetry().speed_setpoint_mps);
  sim.advance(60.0);
  EXPECT_NEAR(0.7, sim.surge().speed_mps, 0.01);
}

TEST(Stop, StopKeepsTheCruiseSpeedForTheNextGuidanceCommand) {
  Simulation sim = started(open_water());
  ASSERT_TRUE(sim.set_speed(0.4).ok());
  ASSERT_TRUE(sim.goto_xy(0.0, 500.0).ok());
  sim.advance(60.0);
  ASSERT_TRUE(sim.stop().ok());
  EXPECT_EQ(0.0, sim.telemetry().speed_setpoint_mps);
  EXPECT_EQ(0.4, sim.cruise_speed_mps());
  sim.advance(60.0);
  ASSERT_TRUE(sim.goto_xy(0.0, 500.0).ok());
  EXPECT_EQ(0.4, sim.telemetry().speed_setpoint_mps);  // not the 0.8 of the parameter file
  sim.advance(90.0);
  EXPECT_NEAR(0.4, sim.surge().speed_mps, 0.01);
}

// ---- loiter and hold_position ---------------------------------------------------------

TEST(Loiter, CirclesTheCentreClockwiseAtItsRadius) {
  Simulation sim = started(open_water());
  ASSERT_FALSE(sim.loiter(50.0, 0.0, 4.0).ok());  // tighter than the vehicle turns
  ASSERT_TRUE(sim.loiter(50.0, 0.0, 20.0).ok());
  ASSERT_GT(steps_until(
                sim, [&] { return sim.waypoint_reached(); }, 200.0),
            0.0);
  sim.advance(60.0);
  double lo = 1e9, hi = 0.0, turned = 0.0;
  double last = std::atan2(sim.pose().x_m - 50.0, sim.pose().y_m);
  for (int i = 0; i < 3000; ++i) {  // five minutes: a lap is 2 pi 20 / 0.8 = 157 s
    sim.step();
    const double r = distance_to(sim, 50.0, 0.0);
    lo = std::min(lo, r);
    hi = std::max(hi, r);
    const double now = std::atan2(sim.pose().x_m - 50.0, sim.pose().y_m);
    turned += std::remainder(now - last, 2.0 * std::numbers::pi);
    last = now;
  }
  EXPECT_GT(lo, 16.0);
  EXPECT_LT(hi, 24.0);
  EXPECT_GT(turned, 2.0 * std::numbers::pi * 1.5);  // clockwise: the bearing from the centre grows
  EXPECT_EQ(GuidanceMode::Loiter, sim.guidance().mode);
}

TEST(HoldPosition, StationKeepingStaysNearThePointInACurrent) {
  Simulation sim = started(open_water("current_x_mps = -0.1\n"));
  sim.advance(120.0);  // fixes learn the current
  ASSERT_TRUE(sim.goto_xy(0.0, 60.0).ok());
  sim.advance(40.0);  // under way
  const double x = sim.navigator().x_m(), y = sim.navigator().y_m();
  ASSERT_TRUE(sim.hold_position().ok());
  EXPECT_TRUE(sim.waypoint_reached());
  EXPECT_EQ(GuidanceMode::Hold, sim.guidance().mode);
  double worst = 0.0;
  for (int i = 0; i < 6000; ++i) {
    sim.step();
    worst = std::max(worst, distance_to(sim, x, y));
  }
  EXPECT_LT(worst, 12.0);  // it coasts on first, then comes back
  EXPECT_LT(distance_to(sim, x, y), 6.0);
  // Adrift instead, the current carries it 60 m in ten minutes.
}

// ---- set_timer, gps_available, system_problem ------------------------------------------------

TEST(SetTimer, TheTimerRunsOutAfterItsOwnLimit) {
  Simulation sim = started(open_water());
  EXPECT_FALSE(sim.set_timer(0.0).ok());
  EXPECT_FALSE(sim.set_timer(NAN).ok());
  ASSERT_TRUE(sim.set_timer(2.5).ok());
  sim.advance(2.4);
  EXPECT_FALSE(sim.time_out());
  sim.advance(0.1);
  EXPECT_TRUE(sim.time_out());
}

TEST(GpsAvailable, OnlyAtTheSurfaceInOpenWaterWithAWorkingReceiver) {
  Simulation sim = started(open_water());
  EXPECT_TRUE(sim.gps_available());
  ASSERT_TRUE(sim.goto_depth(3.0).ok());
  sim.advance(30.0);
  EXPECT_FALSE(sim.gps_available());  // the antenna is under water
  EXPECT_FALSE(sim.gps_fix().ok());
  ASSERT_TRUE(sim.surface().ok());
  ASSERT_GT(steps_until(
                sim, [&] { return sim.gps_available(); }, 60.0),
            0.0);
  EXPECT_TRUE(sim.gps_fix().ok());

  Simulation tank(default_params(), Scenario::nominal());
  ASSERT_TRUE(tank.start_network().ok());
  EXPECT_FALSE(tank.gps_available());

  Simulation dead = started(open_water("[[fault]]\nkind = \"no_gps\"\nat_s = 5\n"));
  EXPECT_TRUE(dead.gps_available());
  dead.advance(5.0);
  EXPECT_FALSE(dead.gps_available());
  EXPECT_FALSE(dead.gps_fix().ok());
}

struct FaultCase {
  std::string toml;
  bool problem;
};

TEST(SystemProblem, ALeakAndADepthCellDropoutAreProblemsLatchedTheOthersAreNot) {
  const FaultCase cases[] = {
      {"kind = \"leak\"\nat_s = 1\n", true},
      {"kind = \"sensor_dropout\"\nat_s = 1\nduration_s = 0.5\n", true},
      {"kind = \"weak_thrusters\"\nat_s = 1\nhealth = 0.1\n", false},
      {"kind = \"compass_bias\"\nat_s = 1\nbias_deg = 10\n", false},
      {"kind = \"altimeter_dead\"\nat_s = 1\n", false},
      {"kind = \"no_gps\"\nat_s = 1\n", false},
      {"kind = \"link_loss\"\nat_s = 1\nduration_s = 1\n", false},
  };
  for (const FaultCase& c : cases) {
    SCOPED_TRACE(c.toml);
    auto s = parse_scenario("seed = 3\n[[fault]]\n" + c.toml, "fault.toml");
    ASSERT_TRUE(s.ok()) << s.error().message;
    Simulation sim(default_params(), s.value());
    sim.advance(0.9);
    EXPECT_FALSE(sim.system_problem());
    sim.advance(0.1);
    EXPECT_EQ(c.problem, sim.system_problem());
    sim.advance(10.0);  // a dropout's readings are back: still reported
    EXPECT_EQ(c.problem, sim.system_problem());
  }
}

}  // namespace
}  // namespace strata::vehicle
