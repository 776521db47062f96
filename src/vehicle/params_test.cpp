#include "vehicle/params.h"

#include <sys/stat.h>
#include <unistd.h>

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
  EXPECT_EQ("/nonexistent/phoenix.toml: cannot open file", p.error().message);
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
