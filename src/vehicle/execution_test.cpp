// The Execution level's function table on the Simulation: the heading and
// sonar functions as the wire names them.
#include "vehicle/execution.h"

#include <cmath>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include <gtest/gtest.h>

namespace strata::vehicle {
namespace {

using protocol::Value;

Outcome exec(Simulation& sim, std::string name, std::vector<Value> args = {}) {
  return execute(sim, protocol::make_exec(1, std::move(name), std::move(args)));
}

bool ask(Simulation& sim, std::string name) {
  const Outcome o = execute(sim, protocol::make_ask(1, std::move(name)));
  EXPECT_FALSE(o.refused.has_value()) << o.message;
  return o.value;
}

Scenario with_target() {
  Scenario s = Scenario::nominal();
  s.vehicle_x_m = 6.0;
  s.vehicle_y_m = 2.0;
  s.target = Target{6.0, 6.0, 0.3};
  return s;
}

TEST(Execution, HeadingTurnsTheVehicleAndHeadingReachedSaysWhenItIsThere) {
  Simulation sim(default_params(), Scenario::nominal());
  EXPECT_FALSE(exec(sim, "heading", {Value::integer(90)}).value);  // network down
  ASSERT_TRUE(execute(sim, protocol::make_ood(1, "start_network")).value);
  EXPECT_FALSE(ask(sim, "heading_reached"));
  EXPECT_TRUE(exec(sim, "heading", {Value::integer(90)}).value);
  EXPECT_FALSE(ask(sim, "heading_reached"));
  sim.advance(15.0);
  EXPECT_TRUE(ask(sim, "heading_reached"));
  EXPECT_NEAR(90.0, sim.yaw().heading_deg, 3.0);

  const Outcome bad = exec(sim, "heading", {Value::real(400.0)});
  EXPECT_FALSE(bad.refused.has_value());
  EXPECT_FALSE(bad.value);
  EXPECT_EQ("heading 400 deg outside 0 to 360 deg", bad.message);
  EXPECT_EQ(protocol::ErrorCode::BadArgument, exec(sim, "heading").refused);
  EXPECT_EQ(protocol::ErrorCode::BadArgument, exec(sim, "heading", {Value::string("east")}).refused);
  EXPECT_EQ(protocol::ErrorCode::UnknownFunction, execute(sim, protocol::make_ask(1, "heading")).refused);
}

TEST(Execution, TheSonarStartsStopsAndDetects) {
  Simulation sim(default_params(), with_target());
  ASSERT_TRUE(execute(sim, protocol::make_ood(1, "start_network")).value);
  EXPECT_FALSE(ask(sim, "target_detected"));
  EXPECT_TRUE(exec(sim, "start_sonar").value);
  EXPECT_TRUE(sim.sonar_on());
  sim.advance(3.4);
  EXPECT_TRUE(ask(sim, "target_detected"));
  EXPECT_TRUE(exec(sim, "stop_sonar").value);
  EXPECT_FALSE(sim.sonar_on());
  EXPECT_FALSE(ask(sim, "target_detected"));
  EXPECT_EQ(protocol::ErrorCode::BadArgument, exec(sim, "start_sonar", {Value::integer(1)}).refused);
}

TEST(Execution, TheInterfaceListsTheNewFunctions) {
  const std::string text = interface_text();
  for (const char* f : {"heading[deg]", "start_sonar", "stop_sonar", "heading_reached", "target_detected"}) {
    EXPECT_NE(std::string::npos, text.find(f)) << f;
  }
  ASSERT_NE(nullptr, find_function(protocol::Verb::Exec, "heading"));
  EXPECT_EQ(1u, find_function(protocol::Verb::Exec, "heading")->args.size());
}

Scenario open_water() {
  Scenario s = Scenario::nominal();
  s.world.open_water = true;
  return s;
}

TEST(Execution, OpenWaterFunctionsDriveTheVehicleAndTheAsksAnswer) {
  Simulation sim(default_params(), open_water());
  ASSERT_TRUE(execute(sim, protocol::make_ood(1, "start_network")).value);
  EXPECT_TRUE(exec(sim, "gps_fix").value);  // at the surface
  sim.advance(120.0);                       // fixes at the surface learn the current (none here)
  EXPECT_TRUE(exec(sim, "set_altitude_floor", {Value::integer(3)}).value);
  EXPECT_TRUE(exec(sim, "goto_depth", {Value::real(2.5)}).value);
  EXPECT_TRUE(exec(sim, "set_speed", {Value::real(0.6)}).value);
  EXPECT_TRUE(exec(sim, "goto_xy", {Value::integer(30), Value::integer(40)}).value);
  EXPECT_FALSE(ask(sim, "waypoint_reached"));
  sim.advance(150.0);
  EXPECT_TRUE(ask(sim, "waypoint_reached"));
  EXPECT_FALSE(ask(sim, "altitude_low"));  // 30 m flat seabed
  EXPECT_FALSE(ask(sim, "position_uncertain"));
  EXPECT_NEAR(2.5, sim.heave().depth_m, 0.2);
  // There the guidance ended: the vehicle holds the waypoint.
  EXPECT_EQ(GuidanceMode::Hold, sim.guidance().mode);
  EXPECT_LT(std::hypot(sim.pose().x_m - 30.0, sim.pose().y_m - 40.0), 8.0);
  EXPECT_FALSE(ask(sim, "gps_available"));
  const Outcome below = exec(sim, "gps_fix");
  EXPECT_FALSE(below.value);
  EXPECT_EQ(0u, below.message.find("no GPS fix at 2."));
  EXPECT_TRUE(
      exec(sim, "track", {Value::integer(30), Value::integer(40), Value::integer(30), Value::integer(400)}).value);
  EXPECT_FALSE(ask(sim, "waypoint_reached"));
  EXPECT_TRUE(exec(sim, "stop").value);
  EXPECT_EQ(GuidanceMode::None, sim.guidance().mode);
}

TEST(Execution, RowsLoiterHoldAndTheTimerAsTheWireNamesThem) {
  Simulation sim(default_params(), open_water());
  ASSERT_TRUE(execute(sim, protocol::make_ood(1, "start_network")).value);
  EXPECT_TRUE(ask(sim, "gps_available"));
  EXPECT_FALSE(ask(sim, "rows_done"));
  const Outcome no_pattern = exec(sim, "next_row");
  EXPECT_EQ(protocol::ErrorCode::Failed, no_pattern.refused);
  EXPECT_EQ("next_row: no row pattern (start_rows first)", no_pattern.message);
  EXPECT_TRUE(exec(sim, "start_rows",
                   {Value::integer(0), Value::integer(0), Value::integer(90), Value::integer(50), Value::integer(-10),
                    Value::integer(1)})
                  .value);
  const Outcome half = exec(sim, "start_rows",
                            {Value::integer(0), Value::integer(0), Value::integer(90), Value::integer(50),
                             Value::integer(10), Value::real(1.5)});
  EXPECT_FALSE(half.refused.has_value());
  EXPECT_FALSE(half.value);
  EXPECT_EQ("row count 1.5 is not a whole number from 1 to 1000", half.message);
  EXPECT_TRUE(exec(sim, "next_row").value);
  EXPECT_TRUE(ask(sim, "rows_done"));
  EXPECT_EQ(GuidanceMode::Track, sim.guidance().mode);
  const Outcome past = exec(sim, "next_row");  // past the last row: the mission's mistake
  EXPECT_EQ(protocol::ErrorCode::Failed, past.refused);
  EXPECT_EQ("next_row: no row left (all 1 rows started)", past.message);
  EXPECT_TRUE(exec(sim, "loiter", {Value::integer(0), Value::integer(0), Value::integer(10)}).value);
  EXPECT_EQ(GuidanceMode::Loiter, sim.guidance().mode);
  EXPECT_TRUE(exec(sim, "hold_position").value);
  EXPECT_EQ(GuidanceMode::Hold, sim.guidance().mode);
  EXPECT_TRUE(ask(sim, "waypoint_reached"));
  EXPECT_TRUE(exec(sim, "set_timer", {Value::integer(3)}).value);
  EXPECT_FALSE(ask(sim, "time_out"));
  sim.advance(3.0);
  EXPECT_TRUE(ask(sim, "time_out"));
  EXPECT_FALSE(exec(sim, "set_timer", {Value::integer(0)}).value);
  EXPECT_EQ(protocol::ErrorCode::BadArgument, exec(sim, "loiter", {Value::integer(0)}).refused);
}

TEST(Execution, HostileArgumentsAreRefusedNeverObeyed) {
  Simulation sim(default_params(), open_water());
  ASSERT_TRUE(execute(sim, protocol::make_ood(1, "start_network")).value);
  const double nan = std::nan("");
  EXPECT_EQ(protocol::ErrorCode::BadArgument, exec(sim, "goto_xy", {Value::real(nan), Value::integer(0)}).refused);
  EXPECT_EQ(protocol::ErrorCode::BadArgument, exec(sim, "set_speed", {Value::real(INFINITY)}).refused);
  EXPECT_EQ(protocol::ErrorCode::BadArgument, exec(sim, "set_sway", {Value::real(nan)}).refused);
  EXPECT_EQ(protocol::ErrorCode::BadArgument, exec(sim, "set_sway", {Value::real(-INFINITY)}).refused);
  EXPECT_EQ(protocol::ErrorCode::BadArgument, exec(sim, "set_sway", {}).refused);
  EXPECT_EQ(protocol::ErrorCode::BadArgument, exec(sim, "track", {Value::integer(1)}).refused);
  EXPECT_EQ(protocol::ErrorCode::BadArgument, exec(sim, "goto_depth", {Value::string("deep")}).refused);
  const Outcome far = exec(sim, "goto_xy", {Value::real(1e300), Value::real(-1e300)});
  EXPECT_FALSE(far.refused.has_value());
  EXPECT_FALSE(far.value);
  EXPECT_NE(std::string::npos, far.message.find("farther than the longest leg"));
  EXPECT_FALSE(exec(sim, "set_speed", {Value::real(1e9)}).value);
  const Outcome sideways = exec(sim, "set_sway", {Value::real(-0.5)});  // beyond the top sway speed
  EXPECT_FALSE(sideways.refused.has_value());
  EXPECT_FALSE(sideways.value);
  EXPECT_NE(std::string::npos, sideways.message.find("top sway speed"));
  EXPECT_TRUE(exec(sim, "set_sway", {Value::real(-0.2)}).value);
  EXPECT_FALSE(exec(sim, "goto_depth", {Value::real(-1)}).value);
  EXPECT_FALSE(exec(sim, "set_altitude_floor", {Value::real(1e18)}).value);
  EXPECT_EQ(GuidanceMode::None, sim.guidance().mode);
  EXPECT_EQ(ControlMode::Idle, sim.telemetry().mode);
}

TEST(Execution, TheInterfaceListsTheOpenWaterFunctions) {
  const std::string text = interface_text();
  for (const char* f : {"goto_depth depth[m]", "set_speed speed[m/s]", "set_sway speed[m/s]", "goto_xy x[m] y[m]",
                        "track x0[m] y0[m] x1[m] y1[m]", "stop ", "gps_fix", "set_altitude_floor floor[m]",
                        "waypoint_reached", "altitude_low", "position_uncertain"}) {
    EXPECT_NE(std::string::npos, text.find(f)) << f;
  }
}

// docs/protocol.md §8 lists the function table: every row names a function
// the vehicle has, under its verb, and every function has its row.
TEST(Execution, TheProtocolDocumentListsExactlyTheFunctionTable) {
  std::ifstream in(std::string(STRATA_SOURCE_DIR) + "/docs/protocol.md");
  ASSERT_TRUE(in.good());
  std::set<std::string> documented;
  const std::regex row(R"(^\| (exec|ask|ood) \| `([a-z_]+))");
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (std::regex_search(line, m, row)) documented.insert(m[1].str() + " " + m[2].str());
  }
  std::set<std::string> table;
  for (const auto& f : function_table()) table.insert(std::string(protocol::verb_name(f.verb)) + " " + f.name);
  EXPECT_EQ(table, documented);
}

}  // namespace
}  // namespace strata::vehicle
