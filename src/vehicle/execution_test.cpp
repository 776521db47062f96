// The Execution level's function table on the Simulation: the heading and
// sonar functions as the wire names them.
#include "vehicle/execution.h"

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

}  // namespace
}  // namespace strata::vehicle
