// The parts of the model one at a time: heave dynamics, depth cell, depth
// filter, depth laws.
#include <cmath>
#include <optional>
#include <vector>

#include <gtest/gtest.h>

#include "vehicle/depth_cell.h"
#include "vehicle/depth_controller.h"
#include "vehicle/depth_filter.h"
#include "vehicle/heave.h"

namespace strata::vehicle {
namespace {

const VehicleParams kP = default_params();

void run_heave(HeaveState& s, double cmd_n, double seconds, double limit_n = 36.0) {
  const int cycles = static_cast<int>(std::lround(seconds / kP.cycle_s));
  for (int i = 0; i < cycles; ++i) advance_heave(kP, cmd_n, limit_n, s);
}

TEST(Heave, FullThrustDownReachesTheDragLimitedSpeed) {
  HeaveState s;
  run_heave(s, 36.0, 18.0);  // about 4 m: still above the bottom
  ASSERT_LT(s.depth_m, kP.tank_depth_m);
  // (36 N - 5 N) = 470 w^2.
  EXPECT_NEAR(std::sqrt(31.0 / 470.0), s.w_mps, 1e-3);
  EXPECT_NEAR(36.0, s.thrust_n, 1e-6);
}

TEST(Heave, ThrustFollowsTheCommandWithAFirstOrderLag) {
  HeaveState s{3.0, 0.0, 0.0};
  run_heave(s, 20.0, kP.thruster_lag_s);
  EXPECT_NEAR(20.0 * (1.0 - std::exp(-1.0)), s.thrust_n, 1e-9);
}

TEST(Heave, ThrustIsLimitedToWhatTheThrustersCanGive) {
  HeaveState s{3.0, 0.0, 0.0};
  run_heave(s, 36.0, 10.0, 3.6);
  EXPECT_NEAR(3.6, s.thrust_n, 1e-6);
  EXPECT_LT(s.w_mps, 0.0);  // 3.6 N down cannot beat 5 N of buoyancy
}

TEST(Heave, ABuoyantVehicleRestsAtTheSurface) {
  HeaveState s{0.5, 0.0, 0.0};
  run_heave(s, 0.0, 30.0);
  EXPECT_EQ(0.0, s.depth_m);
  EXPECT_EQ(0.0, s.w_mps);
  const HeaveContact c = advance_heave(kP, 0.0, 36.0, s);
  EXPECT_TRUE(c.surface);
  EXPECT_FALSE(c.bottom);
}

TEST(Heave, TheBottomStopsTheVehicle) {
  HeaveState s{5.5, 0.0, 0.0};
  run_heave(s, 36.0, 20.0);
  EXPECT_EQ(kP.tank_depth_m, s.depth_m);
  EXPECT_EQ(0.0, s.w_mps);
  EXPECT_TRUE(advance_heave(kP, 36.0, 36.0, s).bottom);
}

TEST(DepthCell, NoiseHasTheConfiguredSpread) {
  DepthCell cell(0.02, 42);
  double sum = 0.0;
  double sum2 = 0.0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const double e = *cell.sample(1.0, false) - 1.0;
    sum += e;
    sum2 += e * e;
  }
  const double mean = sum / n;
  EXPECT_NEAR(0.0, mean, 0.001);
  EXPECT_NEAR(0.02, std::sqrt(sum2 / n - mean * mean), 0.0005);
}

TEST(DepthCell, ADroppedReadingStillUsesItsDeviate) {
  DepthCell a(0.02, 7);
  DepthCell b(0.02, 7);
  (void)a.sample(1.0, false);
  EXPECT_FALSE(b.sample(1.0, true).has_value());
  EXPECT_EQ(a.sample(1.0, false), b.sample(1.0, false));
}

TEST(DepthCell, SameSeedSameReadingsOtherSeedOthers) {
  DepthCell a(0.02, 7);
  DepthCell b(0.02, 7);
  DepthCell c(0.02, 8);
  int differ = 0;
  for (int i = 0; i < 100; ++i) {
    const auto ra = a.sample(2.0, false);
    EXPECT_EQ(ra, b.sample(2.0, false));
    differ += ra != c.sample(2.0, false) ? 1 : 0;
  }
  EXPECT_EQ(100, differ);
}

TEST(DepthFilter, OffUntilStartedThenInitialisesFromAReading) {
  DepthFilter f(0.3, 0.05, 0.1);
  f.update(1.0);
  EXPECT_FALSE(f.on());
  EXPECT_FALSE(f.ready());
  f.start();
  f.update(std::nullopt);
  EXPECT_FALSE(f.ready());
  f.update(1.25);
  EXPECT_TRUE(f.ready());
  EXPECT_EQ(1.25, f.depth_m());
  EXPECT_EQ(0.0, f.rate_mps());
}

TEST(DepthFilter, TracksAConstantRateWithoutLag) {
  DepthFilter f(0.3, 0.05, 0.1);
  f.start();
  double z = 0.0;
  for (int i = 0; i < 300; ++i, z += 0.02) f.update(z);  // 0.2 m/s
  EXPECT_NEAR(0.2, f.rate_mps(), 1e-6);
  EXPECT_NEAR(z - 0.02, f.depth_m(), 1e-6);
}

TEST(DepthFilter, CoastsOnTheRateWithoutReadings) {
  DepthFilter f(0.3, 0.05, 0.1);
  f.start();
  double z = 0.0;
  for (int i = 0; i < 300; ++i, z += 0.02) f.update(z);
  const double depth = f.depth_m();
  for (int i = 0; i < 10; ++i) f.update(std::nullopt);
  EXPECT_NEAR(depth + 0.2, f.depth_m(), 1e-9);
  EXPECT_NEAR(0.2, f.rate_mps(), 1e-6);
}

TEST(DepthLaw, HoldsAtTheSetpointAgainstTheBuoyancy) {
  EXPECT_DOUBLE_EQ(kP.buoyancy_n, sliding_mode_thrust(kP, 2.0, 0.0, 2.0));
}

TEST(DepthLaw, FarFromTheSetpointItUsesFullThrust) {
  EXPECT_DOUBLE_EQ(36.0, sliding_mode_thrust(kP, 0.0, 0.0, 2.0));
  EXPECT_DOUBLE_EQ(-36.0, sliding_mode_thrust(kP, 4.0, 0.0, 2.0));
}

TEST(DepthLaw, BrakesWhenTooFastForTheRemainingDistance) {
  // 0.25 m/s down, 0.2 m to go: the sliding surface wants 0.1 m/s.
  EXPECT_LT(sliding_mode_thrust(kP, 1.8, 0.25, 2.0), 0.0);
}

TEST(SurfaceLaw, FullUpUntilAtTheSurfaceThenOff) {
  EXPECT_DOUBLE_EQ(-36.0, surface_thrust(kP, 1.0));
  EXPECT_DOUBLE_EQ(-36.0, surface_thrust(kP, std::nullopt));
  EXPECT_DOUBLE_EQ(0.0, surface_thrust(kP, kP.surface_depth_m));
  EXPECT_DOUBLE_EQ(0.0, surface_thrust(kP, -0.01));
}

}  // namespace
}  // namespace strata::vehicle
