// The scenario's [world] and [seabed] tables and the open-water faults:
// what they read, and located errors for everything else, hostile input
// included.
#include <string>

#include <gtest/gtest.h>

#include "vehicle/scenario.h"

namespace strata::vehicle {
namespace {

const std::string kOpen = "seed = 1\n[world]\nkind = \"open_water\"\n";

std::string error_of(const std::string& text) {
  auto s = parse_scenario(text, "s.toml");
  EXPECT_FALSE(s.ok());
  return s.ok() ? "" : s.error().message;
}

TEST(ScenarioWorld, TheTankIsTheDefault) {
  auto s = parse_scenario("seed = 1\n", "s.toml");
  ASSERT_TRUE(s.ok());
  EXPECT_FALSE(s.value().world.open_water);
}

TEST(ScenarioWorld, OpenWaterWithACurrentASlopeAndTheNewFaults) {
  auto s = parse_scenario(kOpen +
                              "current_x_mps = 0.1\ncurrent_y_mps = -1.5\n"
                              "[seabed]\nkind = \"slope\"\ndepth_m = 25\nslope_x = 0.02\n"
                              "[vehicle]\nx_m = -120.5\ny_m = 40\n"
                              "[[fault]]\nkind = \"compass_bias\"\nat_s = 3\nbias_deg = -12.5\n"
                              "[[fault]]\nkind = \"altimeter_dead\"\nat_s = 10\n"
                              "[[fault]]\nkind = \"no_gps\"\nat_s = 0\n",
                          "s.toml");
  ASSERT_TRUE(s.ok()) << s.error().message;
  const Scenario& v = s.value();
  EXPECT_TRUE(v.world.open_water);
  EXPECT_DOUBLE_EQ(-1.5, v.world.current_y_mps);
  EXPECT_EQ(SeabedKind::Slope, v.seabed.kind);
  EXPECT_DOUBLE_EQ(25.0 + 0.02 * 100.0, v.seabed.depth_at(100.0, 7.0));
  EXPECT_DOUBLE_EQ(-120.5, *v.vehicle_x_m);
  ASSERT_EQ(3u, v.faults.size());
  EXPECT_EQ(FaultKind::CompassBias, v.faults[0].kind);
  EXPECT_DOUBLE_EQ(-12.5, v.faults[0].bias_deg);
  EXPECT_EQ(FaultKind::AltimeterDead, v.faults[1].kind);
  EXPECT_EQ(FaultKind::NoGps, v.faults[2].kind);
}

TEST(ScenarioWorld, AGridReadsRowByRow) {
  auto s = parse_scenario(kOpen +
                              "[seabed]\nkind = \"grid\"\nx0_m = 0\ny0_m = 0\nspacing_m = 50\nnx = 3\nny = 2\n"
                              "depths_m = [[10, 12, 14], [20, 22, 24]]\n",
                          "s.toml");
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_DOUBLE_EQ(12.0, s.value().seabed.depth_at(50.0, 0.0));
  EXPECT_DOUBLE_EQ(17.0, s.value().seabed.depth_at(50.0, 25.0));
}

TEST(ScenarioWorld, AGridOfTheWrongSizeIsAnErrorAtTheRow) {
  EXPECT_EQ("s.toml:11:27: 'seabed.depths_m' row 2 must hold nx = 3 depths",
            error_of(kOpen + "[seabed]\nkind = \"grid\"\nx0_m = 0\ny0_m = 0\nspacing_m = 50\nnx = 3\nny = 2\n"
                             "depths_m = [[10, 12, 14], [20, 22]]\n"));
  EXPECT_EQ("s.toml:11:12: 'seabed.depths_m' must be an array of ny = 3 rows",
            error_of(kOpen + "[seabed]\nkind = \"grid\"\nx0_m = 0\ny0_m = 0\nspacing_m = 50\nnx = 2\nny = 3\n"
                             "depths_m = [[10, 12], [20, 22]]\n"));
  EXPECT_EQ("s.toml:4:1: grid seabed of 5000 x 3 nodes: at most 10000",
            error_of(kOpen + "[seabed]\nkind = \"grid\"\nnx = 5000\nny = 3\n"));
  EXPECT_EQ("s.toml:6:6: 'seabed.nx' must be an integer in [2, 5000]",
            error_of(kOpen + "[seabed]\nkind = \"grid\"\nnx = 1\n"));
}

TEST(ScenarioWorld, NonFiniteAndHugeNumbersAreLocatedErrors) {
  EXPECT_EQ("s.toml:4:17: 'world.current_x_mps' must be in [-5, 5]", error_of(kOpen + "current_x_mps = nan\n"));
  EXPECT_EQ("s.toml:4:17: 'world.current_y_mps' must be in [-5, 5]", error_of(kOpen + "current_y_mps = -inf\n"));
  EXPECT_EQ("s.toml:2:1: the current must be at most 5 m/s",
            error_of(kOpen + "current_x_mps = 4\ncurrent_y_mps = 4\n"));
  EXPECT_EQ("s.toml:6:11: 'seabed.depth_m' must be in (0, 11000]",
            error_of(kOpen + "[seabed]\nkind = \"flat\"\ndepth_m = 1e308\n"));
  EXPECT_EQ("s.toml:5:7: 'vehicle.x_m' must be within +-100000 m of the origin",
            error_of(kOpen + "[vehicle]\nx_m = inf\n"));
  EXPECT_EQ("s.toml:7:12: 'bias_deg' must be in [-180, 180]",
            error_of(kOpen + "[[fault]]\nkind = \"compass_bias\"\nat_s = 0\nbias_deg = 500\n"));
  EXPECT_EQ("s.toml:11:17: 'seabed.depths_m' must be in (0, 11000]",
            error_of(kOpen + "[seabed]\nkind = \"grid\"\nx0_m = 0\ny0_m = 0\nspacing_m = 1\nnx = 2\nny = 2\n"
                             "depths_m = [[1, nan], [1, 1]]\n"));
}

TEST(ScenarioWorld, OpenWaterKeysInTheTankAreErrors) {
  EXPECT_EQ("s.toml:3:17: a current needs open water ([world] kind = \"open_water\")",
            error_of("seed = 1\n[world]\ncurrent_x_mps = 0.2\n"));
  EXPECT_EQ("s.toml:2:1: [seabed] needs open water ([world] kind = \"open_water\")",
            error_of("seed = 1\n[seabed]\nkind = \"flat\"\ndepth_m = 5\n"));
  EXPECT_EQ("s.toml:3:8: 'world.kind' must be \"tank\" or \"open_water\"",
            error_of("seed = 1\n[world]\nkind = \"sea\"\n"));
  EXPECT_EQ("s.toml:6:1: 'slope_x' is not a key of a flat seabed",
            error_of(kOpen + "[seabed]\nkind = \"flat\"\nslope_x = 0.1\n"));
  EXPECT_EQ("s.toml:4:1: unknown key 'tide' in [world]", error_of(kOpen + "tide = 1\n"));
  EXPECT_EQ("s.toml:4:1: compass_bias fault without 'bias_deg'",
            error_of(kOpen + "[[fault]]\nkind = \"compass_bias\"\nat_s = 0\n"));
}

}  // namespace
}  // namespace strata::vehicle
