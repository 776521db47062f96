#include "vehicle/scenario.h"

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace strata::vehicle {
namespace {

const std::string kDir = std::string(STRATA_SOURCE_DIR) + "/missions/tank/scenarios";

Scenario shipped(const std::string& name) {
  auto s = load_scenario(kDir + "/" + name);
  EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
  return s.ok() ? s.value() : Scenario{};
}

std::string error_of(const std::string& text) {
  auto s = parse_scenario(text, "s.toml");
  EXPECT_FALSE(s.ok());
  return s.ok() ? "" : s.error().message;
}

TEST(Scenario, EveryShippedScenarioParses) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(kDir)) {
    if (entry.path().extension() != ".toml") continue;
    names.push_back(entry.path().filename().string());
    auto s = load_scenario(entry.path().string());
    EXPECT_TRUE(s.ok()) << entry.path() << ": " << (s.ok() ? "" : s.error().message);
    if (s.ok()) {
      EXPECT_FALSE(s.value().description.empty()) << entry.path();
    }
  }
  std::sort(names.begin(), names.end());
  const std::vector<std::string> expected = {"leak_phase2.toml", "leak_phase3.toml", "link_loss.toml", "nominal.toml",
                                             "weak_thrusters.toml"};
  EXPECT_EQ(expected, names);
}

TEST(Scenario, ShippedScenariosSayWhatTheyDo) {
  EXPECT_TRUE(shipped("nominal.toml").faults.empty());

  const Scenario weak = shipped("weak_thrusters.toml");
  ASSERT_EQ(1u, weak.faults.size());
  EXPECT_EQ(FaultKind::WeakThrusters, weak.faults[0].kind);
  // Physically unable to dive: the thrust left is below the net buoyancy.
  EXPECT_LT(2.0 * 18.0 * weak.faults[0].health, 5.0);

  const Scenario leak2 = shipped("leak_phase2.toml");
  ASSERT_EQ(1u, leak2.faults.size());
  EXPECT_EQ(FaultKind::Leak, leak2.faults[0].kind);

  const Scenario link = shipped("link_loss.toml");
  ASSERT_EQ(1u, link.faults.size());
  EXPECT_EQ(FaultKind::LinkLoss, link.faults[0].kind);
  EXPECT_FALSE(link.faults[0].duration_s.has_value());  // forever
  EXPECT_EQ(3.0, link.link_lost_at());
}

TEST(Scenario, ParsesEveryKind) {
  auto s = parse_scenario(R"(seed = 7
description = "all"
[[fault]]
kind = "weak_thrusters"
at_s = 1
health = 0.5
[[fault]]
kind = "leak"
at_s = 2.5
[[fault]]
kind = "sensor_dropout"
at_s = 3.0
duration_s = 1.5
[[fault]]
kind = "link_loss"
at_s = 4.0
duration_s = 2.0
)",
                          "s.toml");
  ASSERT_TRUE(s.ok()) << s.error().message;
  const Scenario& sc = s.value();
  EXPECT_EQ(7u, sc.seed);
  EXPECT_EQ("all", sc.description);
  ASSERT_EQ(4u, sc.faults.size());
  EXPECT_EQ((Fault{FaultKind::WeakThrusters, 1.0, 0.5, std::nullopt}), sc.faults[0]);
  EXPECT_EQ((Fault{FaultKind::Leak, 2.5, 1.0, std::nullopt}), sc.faults[1]);
  EXPECT_EQ((Fault{FaultKind::SensorDropout, 3.0, 1.0, 1.5}), sc.faults[2]);
  EXPECT_EQ((Fault{FaultKind::LinkLoss, 4.0, 1.0, 2.0}), sc.faults[3]);
}

TEST(Scenario, LinkLossWindows) {
  Scenario s = Scenario::nominal();
  EXPECT_FALSE(s.link_lost_at().has_value());
  s.faults.push_back({FaultKind::LinkLoss, 4.0, 1.0, 2.0});
  s.faults.push_back({FaultKind::LinkLoss, 10.0, 1.0, std::nullopt});
  EXPECT_EQ(4.0, s.link_lost_at());
  EXPECT_FALSE(s.link_lost(3.9));
  EXPECT_TRUE(s.link_lost(4.0));
  EXPECT_TRUE(s.link_lost(5.9));
  EXPECT_FALSE(s.link_lost(6.0));
  EXPECT_FALSE(s.link_lost(9.9));
  EXPECT_TRUE(s.link_lost(10.0));
  EXPECT_TRUE(s.link_lost(1e6));
}

TEST(Scenario, UnknownKindCarriesLineAndColumn) {
  EXPECT_EQ(
      "s.toml:3:8: unknown fault kind 'flood' (expected weak_thrusters, leak, "
      "sensor_dropout, link_loss, compass_bias, altimeter_dead or no_gps)",
      error_of("seed = 1\n[[fault]]\nkind = \"flood\"\nat_s = 1\n"));
}

TEST(Scenario, UnknownKeyCarriesLineAndColumn) {
  EXPECT_EQ("s.toml:4:1: unknown key 'health' for a leak fault",
            error_of("seed = 1\n[[fault]]\nkind = \"leak\"\nhealth = 0.5\nat_s = 1\n"));
  EXPECT_EQ("s.toml:2:1: unknown key 'sed'", error_of("seed = 1\nsed = 2\n"));
}

TEST(Scenario, FieldErrorsCarryLineAndColumn) {
  EXPECT_EQ("s.toml:4:8: 'at_s' must be >= 0", error_of("seed = 1\n[[fault]]\nkind = \"leak\"\nat_s = -1\n"));
  EXPECT_EQ("s.toml:5:10: 'health' must be in [0, 1]",
            error_of("seed = 1\n[[fault]]\nkind = \"weak_thrusters\"\nat_s = 0\nhealth = 2\n"));
  EXPECT_EQ("s.toml:1:8: 'seed' must be an integer >= 0", error_of("seed = -3\n"));
  EXPECT_EQ("s.toml:5:14: 'duration_s' must be > 0",
            error_of("seed = 1\n[[fault]]\nkind = \"sensor_dropout\"\nat_s = 0\n"
                     "duration_s = 0\n"));
  EXPECT_EQ("s.toml:5:14: give either 'duration_s' or 'forever = true', not both",
            error_of("seed = 1\n[[fault]]\nkind = \"link_loss\"\nat_s = 0\n"
                     "duration_s = 2\nforever = true\n"));
}

TEST(Scenario, MissingFieldsAreErrors) {
  EXPECT_EQ("s.toml: missing 'seed'", error_of("description = \"x\"\n"));
  EXPECT_EQ(0u, error_of("seed = 1\n[[fault]]\nkind = \"leak\"\n").find("s.toml:2:"));
  EXPECT_NE(std::string::npos, error_of("seed = 1\n[[fault]]\nkind = \"link_loss\"\nat_s = 1\n")
                                   .find("link_loss fault needs 'duration_s' or 'forever = true'"));
}

TEST(Scenario, VehiclePoseAndTargetAreOptional) {
  const Scenario plain = shipped("nominal.toml");
  EXPECT_FALSE(plain.vehicle_x_m.has_value());
  EXPECT_FALSE(plain.vehicle_y_m.has_value());
  EXPECT_EQ(0.0, plain.vehicle_heading_deg);
  EXPECT_FALSE(plain.target.has_value());

  auto s = parse_scenario(
      "seed = 2\n[vehicle]\nx_m = 3\ny_m = 2.5\nheading_deg = 270\n"
      "[target]\nx_m = 9.0\ny_m = 6\nradius_m = 0.25\n",
      "s.toml");
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ(3.0, s.value().vehicle_x_m);
  EXPECT_EQ(2.5, s.value().vehicle_y_m);
  EXPECT_EQ(270.0, s.value().vehicle_heading_deg);
  EXPECT_EQ((Target{9.0, 6.0, 0.25}), s.value().target);

  auto heading_only = parse_scenario("seed = 2\n[vehicle]\nheading_deg = 45\n", "s.toml");
  ASSERT_TRUE(heading_only.ok()) << heading_only.error().message;
  EXPECT_FALSE(heading_only.value().vehicle_x_m.has_value());
  EXPECT_EQ(45.0, heading_only.value().vehicle_heading_deg);
}

TEST(Scenario, VehicleAndTargetErrorsCarryLineAndColumn) {
  EXPECT_EQ("s.toml:3:1: unknown key 'z_m' in [vehicle]", error_of("seed = 1\n[vehicle]\nz_m = 1\n"));
  EXPECT_EQ("s.toml:3:15: 'vehicle.heading_deg' must be in [0, 360)",
            error_of("seed = 1\n[vehicle]\nheading_deg = 360\n"));
  EXPECT_EQ("s.toml:3:7: 'vehicle.x_m' must be >= 0", error_of("seed = 1\n[vehicle]\nx_m = -1\n"));
  EXPECT_EQ("s.toml:3:7: 'vehicle.y_m' must be a number", error_of("seed = 1\n[vehicle]\ny_m = \"centre\"\n"));
  EXPECT_EQ("s.toml:2:11: 'vehicle' must be a table", error_of("seed = 1\nvehicle = 3\n"));
  EXPECT_EQ("s.toml:5:12: 'target.radius_m' must be > 0",
            error_of("seed = 1\n[target]\nx_m = 1\ny_m = 1\nradius_m = 0\n"));
  EXPECT_EQ(0u, error_of("seed = 1\n[target]\nx_m = 1\ny_m = 1\n").find("s.toml:2:1: target without 'radius_m'"));
  EXPECT_EQ("s.toml:3:1: unknown key 'r' in [target]", error_of("seed = 1\n[target]\nr = 1\n"));
}

TEST(Scenario, SyntaxErrorCarriesLineAndColumn) { EXPECT_EQ(0u, error_of("seed = 1\n[[fault]\n").find("s.toml:2:")); }

}  // namespace
}  // namespace strata::vehicle
