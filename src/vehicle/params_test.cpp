#include "vehicle/params.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "core/test_fifo.h"

namespace strata::vehicle {
namespace {

const std::string kShipped = std::string(STRATA_SOURCE_DIR) + "/config/phoenix.toml";

std::string shipped_text() {
  std::ifstream in(kShipped);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The shipped text with the first occurrence of `from` replaced by `to`.
std::string edited(const std::string& from, const std::string& to) {
  std::string text = shipped_text();
  const auto at = text.find(from);
  EXPECT_NE(std::string::npos, at) << from;
  return text.replace(at, from.size(), to);
}

// 1-based line of the first occurrence of `needle` in the shipped file.
int line_of(const std::string& needle) {
  const std::string text = shipped_text();
  const auto at = text.find(needle);
  int line = 1;
  for (std::size_t i = 0; i < at; ++i) line += text[i] == '\n' ? 1 : 0;
  return line;
}

std::string params_error_of(const std::string& text) {
  auto p = parse_params(text, "p.toml");
  EXPECT_FALSE(p.ok());
  return p.ok() ? "" : p.error().message;
}

TEST(Params, ShippedFileParsesAndEqualsTheBuiltInDefaults) {
  auto p = load_params(kShipped);
  ASSERT_TRUE(p.ok()) << p.error().message;
  EXPECT_EQ(default_params(), p.value());
}

TEST(Params, DefaultsAreTheDesignEstimates) {
  const VehicleParams p = default_params();
  EXPECT_DOUBLE_EQ(175.0, p.mass_kg);
  EXPECT_DOUBLE_EQ(425.0, p.total_mass_kg());
  EXPECT_DOUBLE_EQ(36.0, p.max_total_thrust_n());
  EXPECT_DOUBLE_EQ(0.1, p.cycle_s);
  // The vehicle floats when the thrusters stop, and can dive against it.
  EXPECT_GT(p.buoyancy_n, 0.0);
  EXPECT_GT(p.max_total_thrust_n(), p.buoyancy_n);
}

TEST(Params, YawAndSonarDefaultsAreTheDesignEstimates) {
  const VehicleParams p = default_params();
  EXPECT_DOUBLE_EQ(126.0, p.total_yaw_inertia_kgm2());
  EXPECT_DOUBLE_EQ(10.8, p.max_yaw_moment_nm());  // 2 x 9 N x 0.6 m
  // The heading law's switching gain is within what the thrusters give.
  EXPECT_LT(p.hdg_gain_nm, p.max_yaw_moment_nm());
  EXPECT_DOUBLE_EQ(0.05, p.sonar_range_m / p.sonar_bins);  // 5 cm bins
  EXPECT_DOUBLE_EQ(0.05, p.sonar_ping_period_s);
  EXPECT_LT(p.sonar_noise, p.sonar_detect_threshold);
}

TEST(Params, TheNewTablesAreRequiredAndRangeChecked) {
  EXPECT_EQ("p.toml: missing key 'yaw.lever_arm_m'", params_error_of(edited("lever_arm_m = 0.6", "")));
  EXPECT_EQ("p.toml: missing key 'sonar.bins'", params_error_of(edited("bins = 200", "")));
  EXPECT_EQ("p.toml: missing key 'tank.width_y_m'", params_error_of(edited("width_y_m = 8.0", "")));
  const int line = line_of("bins = 200");
  EXPECT_EQ(0u, params_error_of(edited("bins = 200", "bins = 5000"))
                    .find("p.toml:" + std::to_string(line) + ":8: 'sonar.bins' = 5000 is out of range"));
  EXPECT_NE(std::string::npos, params_error_of(edited("heading_tolerance_deg = 3.0", "heading_tolerance_deg = 0"))
                                   .find("'detection.heading_tolerance_deg' = 0 is out of range"));
}

TEST(Params, SyntaxErrorCarriesLineAndColumn) {
  const std::string e = params_error_of("[hull]\nmass_kg = = 3\n");
  EXPECT_EQ(0u, e.find("p.toml:2:")) << e;
}

TEST(Params, UnknownKeyCarriesLineAndColumn) {
  const int line = line_of("mass_kg = 175.0");
  const std::string e = params_error_of(edited("mass_kg = 175.0", "mass_kgs = 175.0"));
  EXPECT_EQ("p.toml:" + std::to_string(line) + ":1: unknown key 'hull.mass_kgs'", e);
}

TEST(Params, UnknownTableCarriesLineAndColumn) {
  const int line = line_of("[watchdog]");
  const std::string e = params_error_of(edited("[watchdog]", "[watchdogs]"));
  EXPECT_EQ("p.toml:" + std::to_string(line) + ":2: unknown table 'watchdogs'", e);
}

TEST(Params, OutOfRangeValueCarriesLineAndColumn) {
  const int line = line_of("cycle_s = 0.1");
  const std::string e = params_error_of(edited("cycle_s = 0.1", "cycle_s = -0.1"));
  EXPECT_EQ(0u, e.find("p.toml:" + std::to_string(line) +
                       ":11: 'simulation.cycle_s' = -0.1 "
                       "is out of range"))
      << e;
}

TEST(Params, IntegerKeyRejectsAFloat) {
  const int line = line_of("substeps = 10");
  const std::string e = params_error_of(edited("substeps = 10", "substeps = 10.5"));
  EXPECT_EQ("p.toml:" + std::to_string(line) + ":12: 'simulation.substeps' must be an integer", e);
}

TEST(Params, NonNumberIsAnError) {
  const int line = line_of("noise_m = 0.02");
  const std::string e = params_error_of(edited("noise_m = 0.02", "noise_m = \"2 cm\""));
  EXPECT_EQ("p.toml:" + std::to_string(line) + ":11: 'depth_cell.noise_m' must be a number", e);
}

TEST(Params, MissingKeyIsNamed) {
  const std::string e = params_error_of(edited("lag_s = 0.3", ""));
  EXPECT_EQ("p.toml: missing key 'thrusters.lag_s'", e);
}

TEST(Params, IntegersAreAcceptedForReals) {
  auto p = parse_params(edited("mass_kg = 175.0", "mass_kg = 180"), "p.toml");
  ASSERT_TRUE(p.ok()) << p.error().message;
  EXPECT_DOUBLE_EQ(180.0, p.value().mass_kg);
}

TEST(Params, MissingFileIsAnIoError) {
  auto p = load_params("/nonexistent/phoenix.toml");
  ASSERT_FALSE(p.ok());
  EXPECT_EQ(core::ErrorCode::Io, p.error().code);
  // With the system's reason (a missing file, a link loop, no permission).
  EXPECT_EQ("/nonexistent/phoenix.toml: cannot open file: No such file or directory", p.error().message);
}

TEST(Params, AFifoGivenAsTheParametersIsAnErrorNotAHang) {
  const auto fifo = core::testing::make_fifo("phoenix.toml");
  ASSERT_FALSE(fifo.empty());
  auto r = load_params(fifo.string());
  std::filesystem::remove_all(fifo.parent_path());
  ASSERT_FALSE(r);
  EXPECT_EQ(core::ErrorCode::Io, r.error().code);
  EXPECT_NE(r.error().message.find("not a regular file"), std::string::npos) << r.error().message;
}

}  // namespace
}  // namespace strata::vehicle

namespace strata::vehicle {
namespace {

TEST(Params, TheOpenWaterTablesAreRequiredAndTheCruiseSpeedWithinTheTopSpeed) {
  EXPECT_EQ("p.toml: missing key 'surge.motor_max_n'", params_error_of(edited("motor_max_n = 12.0", "")));
  EXPECT_EQ("p.toml: missing key 'navigation.gps_noise_m'", params_error_of(edited("gps_noise_m = 1.5", "")));
  EXPECT_EQ(
      "p.toml: guidance.cruise_speed_mps must not exceed the top speed, 0.707 m/s (surge.motor_max_n and "
      "surge.drag_coeff)",
      params_error_of(edited("motor_max_n = 12.0", "motor_max_n = 6.0")));
  EXPECT_EQ("p.toml:" + std::to_string(line_of("drag_coeff = 24.0")) +
                ":14: 'surge.drag_coeff' = 0 is out of range (0 < value)",
            params_error_of(edited("drag_coeff = 24.0", "drag_coeff = 0.0")));
}

}  // namespace
}  // namespace strata::vehicle

namespace strata::vehicle {
namespace {

TEST(VehicleParamsOverride, AParameterSetByItsFileNameLandsInItsField) {
  VehicleParams p;
  ASSERT_TRUE(set_param(p, "hull.mass_kg", 44.5).ok());
  ASSERT_TRUE(set_param(p, "thrusters.max_n", 30).ok());
  ASSERT_TRUE(set_param(p, "simulation.substeps", 20).ok());
  EXPECT_EQ(44.5, p.mass_kg);
  EXPECT_EQ(30.0, p.thruster_max_n);
  EXPECT_EQ(20, p.substeps);
  EXPECT_EQ(default_params().drag_coeff, p.drag_coeff) << "only the named fields move";
}

TEST(VehicleParamsOverride, UnknownNamesAndValuesTheFileWouldRefuseAreRefused) {
  VehicleParams p;
  EXPECT_EQ("unknown vehicle parameter 'mass_kg'", set_param(p, "mass_kg", 40).error().message);
  EXPECT_EQ("'hull.mass_kg' = 0 is out of range (0 < value)", set_param(p, "hull.mass_kg", 0).error().message);
  EXPECT_FALSE(set_param(p, "hull.mass_kg", std::nan("")).ok());
  EXPECT_FALSE(set_param(p, "hull.buoyancy_n", INFINITY).ok());
  EXPECT_TRUE(set_param(p, "hull.buoyancy_n", -3).ok());
  EXPECT_EQ("'simulation.substeps' = 2.5 is not a whole number",
            set_param(p, "simulation.substeps", 2.5).error().message);
  EXPECT_FALSE(set_param(p, "filter.alpha", 1.5).ok());
  EXPECT_EQ(default_params(), [] {
    VehicleParams q;
    (void)set_param(q, "hull.mass_kg", -1);
    return q;
  }()) << "a refused value changes nothing";
}

TEST(VehicleParamsOverride, TheNamesAreTheShippedFilesKeysAndTheTextReadsBackTheSame) {
  std::size_t found = 0;
  const std::string text = shipped_text();
  for (const ParamInfo& info : param_infos()) {
    const std::string key = info.name.substr(info.name.find('.') + 1);
    found += text.find("\n" + key + " ") != std::string::npos ? 1 : 0;
  }
  EXPECT_EQ(param_infos().size(), found);
  EXPECT_NE(std::string::npos, param_names_text().find("hull: mass_kg, added_mass_kg, drag_coeff, buoyancy_n; "));
  VehicleParams p;
  ASSERT_TRUE(set_param(p, "hull.mass_kg", 0.1 + 0.2).ok());
  ASSERT_TRUE(set_param(p, "navigation.current_walk_mps", 1e-7).ok());
  auto back = parse_params(params_toml(p), "case.toml");
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(p, back.value());
}

TEST(VehicleParamsOverride, RelationsBetweenParametersAreCheckedApart) {
  VehicleParams p;
  ASSERT_TRUE(set_param(p, "detection.surface_depth_m", 7).ok());
  EXPECT_NE(std::string::npos, check_param_relations(p).error().message.find("surface_depth_m must be less than"));
  EXPECT_TRUE(check_param_relations(default_params()).ok());
  std::size_t related = 0;
  for (const ParamInfo& info : param_infos()) related += param_in_relations(info.name) ? 1 : 0;
  EXPECT_EQ(5u, related) << "the five parameters the rules read, each a real one";
  EXPECT_FALSE(param_in_relations("hull.mass_kg"));
}

}  // namespace
}  // namespace strata::vehicle
