#include "tactical/mission_data.h"

#include <gtest/gtest.h>

namespace strata::tactical {
namespace {

const std::string kDataSourceDir = STRATA_SOURCE_DIR;

std::string error_of(const std::string& text, const DataLimits& limits = {}) {
  auto d = MissionData::parse(text, "data.toml", limits);
  EXPECT_FALSE(d.ok());
  return d.ok() ? "" : d.error().message;
}

TEST(MissionData, TheShippedTankDataLoads) {
  auto d = MissionData::load(kDataSourceDir + "/missions/tank/setpoints.toml");
  ASSERT_TRUE(d.ok()) << d.error().message;
  const auto& sp = d.value().setpoints();
  ASSERT_EQ(3u, sp.size());
  EXPECT_EQ("away from surface", sp[0].name);
  EXPECT_EQ(0.6, sp[0].depth_m);
  EXPECT_EQ(30, sp[0].timeout_s);
  EXPECT_EQ(1.5, sp[1].depth_m);
  EXPECT_EQ(45, sp[1].timeout_s);
  EXPECT_EQ(0.0, sp[2].depth_m);
  EXPECT_EQ(60, sp[2].timeout_s);
  EXPECT_EQ("surface", sp[2].name);
}

TEST(MissionData, NameIsOptional) {
  auto d = MissionData::parse("[[setpoint]]\ndepth_m = 1\ntimeout_s = 2.5\n", "data.toml");
  ASSERT_TRUE(d.ok()) << d.error().message;
  EXPECT_EQ("", d.value().setpoints()[0].name);
  EXPECT_EQ(2.5, d.value().setpoints()[0].timeout_s);
  EXPECT_EQ(1u, d.value().setpoints()[0].line);
}

TEST(MissionData, ErrorsCarryLineAndColumn) {
  EXPECT_EQ("data.toml:2:11: setpoint 1: depth_m must be a number of metres, not a string",
            error_of("[[setpoint]]\ndepth_m = \"deep\"\ntimeout_s = 10\n"));
  EXPECT_EQ(
      "data.toml:6:11: setpoint 2: depth_m is -0.5 m; it must lie in 0 .. 6 m (positive down, "
      "within the tank)",
      error_of("[[setpoint]]\ndepth_m = 1\ntimeout_s = 10\n\n[[setpoint]]\ndepth_m = -0.5\n"
               "timeout_s = 10\n"));
  EXPECT_EQ("data.toml:1:1: setpoint 1 has no timeout_s", error_of("[[setpoint]]\ndepth_m = 1\n"));
  EXPECT_EQ("data.toml:4:1: setpoint 1: unknown key 'speed' (known: depth_m, name, timeout_s; docs/mission-data.md)",
            error_of("[[setpoint]]\ndepth_m = 1\ntimeout_s = 10\nspeed = 2\n"));
  EXPECT_EQ("data.toml:3:13: setpoint 1: timeout_s is 0 s; it must be above 0",
            error_of("[[setpoint]]\ndepth_m = 1\ntimeout_s = 0\n"));
  EXPECT_EQ(
      "data.toml:2:11: setpoint 1: depth_m is 12 m; it must lie in 0 .. 10 m (positive down, "
      "within the tank)",
      error_of("[[setpoint]]\ndepth_m = 12\ntimeout_s = 1\n", DataLimits{10.0}));
  EXPECT_EQ("data.toml:2:8: setpoint 1: name must be a string, not an integer",
            error_of("[[setpoint]]\nname = 3\ndepth_m = 1\ntimeout_s = 1\n"));
  EXPECT_EQ(
      "data.toml:2:11: setpoint 1: depth_m is nan m; it must lie in 0 .. 6 m (positive down, "
      "within the tank)",
      error_of("[[setpoint]]\ndepth_m = nan\ntimeout_s = 1\n"));
}

TEST(MissionData, EveryErrorIsReportedInFileOrder) {
  std::string e = error_of("[[setpoint]]\ndepht_m = 1\ntimeout_s = 1\n");
  EXPECT_EQ(
      "data.toml:1:1: setpoint 1 has no depth_m\n"
      "data.toml:2:1: setpoint 1: unknown key 'depht_m': did you mean 'depth_m'? (known: depth_m, name, timeout_s; "
      "docs/mission-data.md)",
      e);
}

TEST(MissionData, EmptyAndMisshapenFiles) {
  EXPECT_EQ(
      "data.toml:1:1: no setpoints: add [[setpoint]] tables with depth_m and timeout_s (or [[waypoint]] tables "
      "with x_m and y_m)",
      error_of(""));
  EXPECT_EQ("data.toml:1:12: the setpoint list is empty", error_of("setpoint = []\n"));
  EXPECT_EQ("data.toml:1:12: 'setpoint' must be an array of tables: write each as [[setpoint]]",
            error_of("setpoint = [1]\n"));
  EXPECT_EQ("data.toml:1:12: 'setpoint' must be an array of tables: write each as [[setpoint]]",
            error_of("setpoint = 1\n"));
  EXPECT_EQ(
      "data.toml:1:1: unknown key 'depth_m' at the top level: mission data holds only "
      "[[setpoint]] and [[waypoint]] tables\n"
      "data.toml:1:1: no setpoints: add [[setpoint]] tables with depth_m and timeout_s (or [[waypoint]] tables "
      "with x_m and y_m)",
      error_of("depth_m = 1\n"));
}

TEST(MissionData, SyntaxErrorsCarryLineAndColumn) {
  EXPECT_EQ(0u, error_of("[[setpoint]]\ndepth_m = 1\ntimeout_s = \n").rfind("data.toml:3:", 0));
}

TEST(MissionData, AMissingFileIsAnIoError) {
  auto d = MissionData::load(kDataSourceDir + "/missions/tank/none.toml");
  ASSERT_FALSE(d.ok());
  EXPECT_EQ(core::ErrorCode::Io, d.error().code);
}

TEST(DataCursor, ServesTheSetpointsInOrderThenFailsClearly) {
  auto d = MissionData::load(kDataSourceDir + "/missions/tank/setpoints.toml");
  ASSERT_TRUE(d.ok());
  DataCursor cursor(d.value());
  EXPECT_EQ(nullptr, cursor.current());
  EXPECT_EQ(0u, cursor.position());
  for (double depth : {0.6, 1.5, 0.0}) {
    auto sp = cursor.next();
    ASSERT_TRUE(sp.ok());
    EXPECT_EQ(depth, sp.value()->depth_m);
    EXPECT_EQ(sp.value(), cursor.current());
  }
  EXPECT_EQ(3u, cursor.position());
  auto past = cursor.next();
  ASSERT_FALSE(past.ok());
  EXPECT_EQ("mission data has 3 setpoints; next_setpt_data was called a 4th time", past.error().message);
  EXPECT_EQ(0.0, cursor.current()->depth_m);  // unchanged
  EXPECT_EQ("mission data has 3 setpoints; next_setpt_data was called a 5th time", cursor.next().error().message);
}

TEST(DataCursor, OneSetpointIsSingular) {
  auto d = MissionData::parse("[[setpoint]]\ndepth_m = 1\ntimeout_s = 1\n", "data.toml");
  ASSERT_TRUE(d.ok());
  DataCursor cursor(d.value());
  ASSERT_TRUE(cursor.next().ok());
  EXPECT_EQ("mission data has 1 setpoint; next_setpt_data was called a 2nd time", cursor.next().error().message);
}

TEST(DataCursor, Ordinals) {
  EXPECT_EQ("1st", ordinal(1));
  EXPECT_EQ("2nd", ordinal(2));
  EXPECT_EQ("3rd", ordinal(3));
  EXPECT_EQ("4th", ordinal(4));
  EXPECT_EQ("11th", ordinal(11));
  EXPECT_EQ("12th", ordinal(12));
  EXPECT_EQ("13th", ordinal(13));
  EXPECT_EQ("21st", ordinal(21));
  EXPECT_EQ("102nd", ordinal(102));
  EXPECT_EQ("111th", ordinal(111));
}

TEST(MissionData, WaypointsAloneMakeMissionData) {
  auto d = MissionData::parse(
      "[[waypoint]]\nname = \"start\"\nx_m = 0\ny_m = -20.5\n[[waypoint]]\nx_m = 200\ny_m = 0\n", "data.toml");
  ASSERT_TRUE(d.ok()) << d.error().message;
  EXPECT_TRUE(d.value().setpoints().empty());
  ASSERT_EQ(2u, d.value().waypoints().size());
  EXPECT_EQ("start", d.value().waypoints()[0].name);
  EXPECT_EQ(-20.5, d.value().waypoints()[0].y_m);
  EXPECT_EQ(5u, d.value().waypoints()[1].line);
  DataCursor cursor(d.value());
  EXPECT_EQ(nullptr, cursor.current_waypoint());
  ASSERT_TRUE(cursor.next_waypoint().ok());
  ASSERT_TRUE(cursor.next_waypoint().ok());
  EXPECT_EQ(200.0, cursor.current_waypoint()->x_m);
  auto past = cursor.next_waypoint();
  ASSERT_FALSE(past.ok());
  EXPECT_EQ("mission data has 2 waypoints; next_waypoint was called a 3rd time", past.error().message);
  EXPECT_EQ(200.0, cursor.current_waypoint()->x_m);
  EXPECT_EQ(0u, cursor.position());  // the setpoint cursor is its own
}

TEST(MissionData, WaypointErrorsCarryLineAndColumn) {
  EXPECT_EQ("data.toml:2:7: waypoint 1: x_m is inf m; it must lie within +-100000 m",
            error_of("[[waypoint]]\nx_m = inf\ny_m = 0\n"));
  EXPECT_EQ("data.toml:3:7: waypoint 1: y_m is 1e+300 m; it must lie within +-100000 m",
            error_of("[[waypoint]]\nx_m = 0\ny_m = 1e300\n"));
  EXPECT_EQ("data.toml:1:1: waypoint 1 has no y_m", error_of("[[waypoint]]\nx_m = 1\n"));
  EXPECT_EQ(
      "data.toml:2:1: waypoint 1: unknown key 'z_m': did you mean 'x_m'? (known: name, x_m, y_m; "
      "docs/mission-data.md)",
      error_of("[[waypoint]]\nz_m = 1\nx_m = 0\ny_m = 0\n"));
}

TEST(MissionData, AWaypointKeyWithoutItsUnitIsNamedWithIt) {
  EXPECT_EQ(
      "data.toml:2:1: waypoint 1: unknown key 'x': did you mean 'x_m'? (known: name, x_m, y_m; "
      "docs/mission-data.md)\n"
      "data.toml:3:1: waypoint 1: unknown key 'y': did you mean 'y_m'? (known: name, x_m, y_m; "
      "docs/mission-data.md)",
      error_of("[[waypoint]]\nx = 1\ny = 2\nx_m = 0\ny_m = 0\n"));
  EXPECT_EQ("data.toml:1:12: the waypoint list is empty", error_of("waypoint = []\n"));
}

}  // namespace
}  // namespace strata::tactical
