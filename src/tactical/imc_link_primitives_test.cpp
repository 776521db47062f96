// The catalogue's primitives over IMC: each is a Reference (or a payload
// switch) on the vehicle's clock, answered from its EstimatedState; what an
// IMC vehicle has no counterpart for is refused, not sent
// (imc_link_test_support.h has the scripted peer).
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tactical/imc_link_test_support.h"

namespace strata::tactical::imc_link_tests {
namespace {

TEST(ImcLink, GotoDepthIsAReferenceWithZAndIsAnsweredAtTheNextStateOnTheVehiclesClock) {
  ImcRig rig;
  rig.connect();
  const double before = rig.vehicle.t_s;
  const std::size_t sent = rig.vehicle.references.size();
  auto r = rig.call(protocol::make_exec(0, "goto_depth", {protocol::Value::real(2.5)}));
  ASSERT_TRUE(r.ok());
  const auto& done = std::get<protocol::Done>(r.value());
  EXPECT_TRUE(done.success);
  // The run's clock starts at the first EstimatedState (0.1 s of the
  // vehicle's); the reply comes with the next one, 0.1 s after `before`.
  EXPECT_DOUBLE_EQ(done.sim_time_s, before);
  ASSERT_TRUE(run_until(rig.io, [&] { return rig.vehicle.references.size() > sent; }));
  const imc::Reference& ref = rig.vehicle.references.back();
  EXPECT_EQ(ref.flags & 0x07, imc::Reference::kFlagLocation | imc::Reference::kFlagSpeed | imc::Reference::kFlagZ);
  ASSERT_TRUE(ref.z);
  EXPECT_FLOAT_EQ(ref.z->value, 2.5f);
  EXPECT_EQ(ref.z->z_units, imc::DesiredZ::kZUnitsDepth);
}

TEST(ImcLink, DepthReachedNeedsZNearForTheReferenceSentAndThePhoenixsTolerance) {
  ImcRig rig;
  rig.connect();
  ASSERT_TRUE(rig.exec("goto_depth", {protocol::Value::integer(2)}));
  rig.vehicle.depth_m = 1.5;  // DUNE says Z_NEAR within 1 m: not yet reached for the Phoenix's 0.1 m
  rig.vehicle.follow_state(imc::FollowRefState::kStateGoto, imc::FollowRefState::kProxZNear);
  EXPECT_FALSE(rig.ask("depth_reached"));
  rig.vehicle.depth_m = 1.97;
  rig.vehicle.follow_state(imc::FollowRefState::kStateGoto, imc::FollowRefState::kProxZNear);
  EXPECT_TRUE(rig.ask("depth_reached"));
  // A new target: the old echo says nothing about it.
  ASSERT_TRUE(rig.exec("goto_depth", {protocol::Value::integer(4)}));
  EXPECT_FALSE(rig.ask("depth_reached"));
}

TEST(ImcLink, GotoXyIsAPointNorthEastOfTheOriginAndWaypointReachedIsXyNear) {
  ImcRig rig;
  rig.connect();
  const imc::Reference ref =
      rig.steer("goto_xy", {protocol::Value::integer(100), protocol::Value::integer(0)});  // east
  EXPECT_NEAR(ref.lat, 0.7188, 1e-9);
  EXPECT_NEAR(ref.lon, -0.1519 + 100.0 / (6378137.0 * std::cos(0.7188)), 1e-12);
  EXPECT_FALSE(rig.ask("waypoint_reached"));
  rig.vehicle.follow_state(imc::FollowRefState::kStateLoiter,
                           imc::FollowRefState::kProxXyNear | imc::FollowRefState::kProxZNear);
  EXPECT_TRUE(rig.ask("waypoint_reached"));
}

TEST(ImcLink, TelemetryIsInStratasFrameXEastYNorth) {
  ImcRig rig;
  rig.connect();
  std::vector<protocol::Telemetry> seen;
  rig.link->on_telemetry([&](const protocol::Telemetry& t) { seen.push_back(t); });
  ASSERT_TRUE(rig.call(protocol::make_telemetry(0, 10)).ok());
  ASSERT_TRUE(run_until(rig.io, [&] { return !seen.empty(); }));
  const std::size_t before = seen.size();
  rig.vehicle.north_m = 10;
  rig.vehicle.east_m = 5;
  rig.vehicle.depth_m = 1.25;
  rig.vehicle.psi_rad = std::numbers::pi / 2;
  rig.vehicle.state(1.0);  // past the next sample's time at 10 Hz
  ASSERT_TRUE(run_until(rig.io, [&] { return seen.size() > before; }));
  EXPECT_EQ(seen.back().extras["x"], "5");
  EXPECT_EQ(seen.back().extras["y"], "10");
  EXPECT_DOUBLE_EQ(*seen.back().depth_m, 1.25);
  EXPECT_NEAR(*seen.back().heading_deg, 90.0, 1e-4);
}

TEST(ImcLink, SleepEndsOnTheVehiclesClockNotTheWallClock) {
  ImcRig rig;
  rig.connect();
  const double start = rig.vehicle.t_s;
  // Cycles of 1 s of the vehicle's time each: the reply comes at the first
  // state at least 3 s after the call, however fast they come.
  auto r = rig.call(protocol::make_exec(0, "sleep", {protocol::Value::integer(3)}), 10, 1.0);
  ASSERT_TRUE(r.ok());
  EXPECT_NEAR(std::get<protocol::Done>(r.value()).sim_time_s - (start - 0.1), 3.0, 1e-9);
}

TEST(ImcLink, TheReferenceStreamStaysAliveAtTwiceASecondOfTheVehiclesTime) {
  ImcRig rig;
  rig.connect();
  ASSERT_TRUE(run_until(rig.io, [&] { return !rig.vehicle.references.empty(); }));
  const std::size_t before = rig.vehicle.references.size();
  for (int i = 0; i < 100; ++i) rig.vehicle.state(0.1);  // 10 s of the vehicle's time
  // A Reference each 0.5 s of it: 20, the last one sent when the last state arrives.
  ASSERT_TRUE(run_until(rig.io, [&] { return rig.vehicle.references.size() - before >= 20; }));
  EXPECT_TRUE(rig.ask("system_problem") == false);  // one more state: at most one more Reference
  EXPECT_LE(rig.vehicle.references.size() - before, 21u);
}

TEST(ImcLink, AVehicleInErrorAnswersSystemProblemAndIsSurfacedByAbort) {
  ImcRig rig;
  rig.connect();
  EXPECT_FALSE(rig.ask("system_problem"));
  rig.vehicle.vehicle_state(imc::VehicleState::kOpModeError, "Leak Sensor - Nose", "Leak Sensor - Nose: leak detected");
  rig.vehicle.plan_reply(imc::PlanControl::kFailure, "vehicle error");
  EXPECT_TRUE(rig.ask("system_problem"));
  EXPECT_TRUE(rig.exec("surface"));
  ASSERT_TRUE(run_until(rig.io, [&] { return rig.vehicle.aborts > 0; }));
  EXPECT_EQ(rig.vehicle.aborts, 1);
  EXPECT_EQ(rig.link->surface_method(), "abort");
  bool named = false;
  for (const auto& e : rig.events)
    named = named || e == "vehicle in ERROR: Leak Sensor - Nose: Leak Sensor - Nose: leak detected";
  EXPECT_TRUE(named);
}

TEST(ImcLink, SurfaceIsAZeroDepthReferenceWhenTheVehicleTakesOne) {
  ImcRig rig;
  rig.connect();
  const imc::Reference ref = rig.steer("surface");
  ASSERT_TRUE(ref.z);
  EXPECT_EQ(ref.z->value, 0.0f);
  EXPECT_EQ(rig.vehicle.aborts, 0);
  EXPECT_EQ(rig.link->surface_method(), "reference");
}

TEST(ImcLink, AStepOfTheVehiclesClockEndsNoDeadline) {
  ImcRig rig;
  rig.connect();
  std::optional<core::Result<protocol::VehicleMessage>> reply;
  rig.link->send(
      protocol::make_exec(0, "sleep", {protocol::Value::integer(30)}), [&](auto m) { reply = std::move(m); },
      std::nullopt, 32.0);
  rig.vehicle.state(10000.0);  // the vehicle set its clock from GPS, or one timestamp far off
  rig.vehicle.state(0.1);
  EXPECT_TRUE(rig.ask("depth_filter_off"));  // two states read: the sleep is not over
  EXPECT_FALSE(reply.has_value());
  bool said = false;
  for (const auto& e : rig.events) said = said || e.find("the vehicle's clock stepped by") != std::string::npos;
  EXPECT_TRUE(said);
  // A timestamp that is no time is dropped, not taken as the clock.
  const std::uint64_t dropped = rig.link->counts().dropped.total();
  imc::Packet nan{{}, imc::Message(imc::EstimatedState{})};
  nan.header.src = kVehicleId;
  nan.header.timestamp = std::numeric_limits<double>::quiet_NaN();
  rig.vehicle.send_raw(imc::encode(nan).value());
  ASSERT_TRUE(run_until(rig.io, [&] { return rig.link->counts().dropped.total() > dropped; }));
  EXPECT_FALSE(reply.has_value());
}

TEST(ImcLink, AFunctionAnImcVehicleHasNotIsRefusedNotSent) {
  ImcRig rig;
  rig.connect();
  auto r = rig.call(protocol::make_exec(0, "set_sway", {protocol::Value::real(0.1)}));
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, core::ErrorCode::InvalidInput) << "the link cannot carry it: refused, not a bad reply";
  EXPECT_EQ(r.error().message, "an IMC vehicle has no 'set_sway' (docs/imc.md)");
}

TEST(ImcLink, TheSonarIsAPayloadSwitchedBySetEntityParameters) {
  ImcRig rig;
  rig.connect();
  const std::size_t before = rig.vehicle.received.size();
  EXPECT_TRUE(rig.exec("start_sonar"));
  const imc::SetEntityParameters* set = nullptr;
  ASSERT_TRUE(run_until(rig.io, [&] {
    for (std::size_t i = before; i < rig.vehicle.received.size() && !set; ++i) {
      set = std::get_if<imc::SetEntityParameters>(&rig.vehicle.received[i].message);
    }
    return set != nullptr;
  }));
  EXPECT_EQ(set->name, "Sidescan");
  ASSERT_EQ(set->params.size(), 1u);
  EXPECT_EQ(set->params[0].name, "Active");
  EXPECT_EQ(set->params[0].value, "true");
}

TEST(ImcLink, PositionUncertainIsTheHorizontalSigmaOfNavigationUncertaintyAboveTheLimit) {
  ImcRig rig;
  rig.connect();
  EXPECT_FALSE(rig.ask("position_uncertain"));  // none heard: not uncertain
  imc::NavigationUncertainty nu;
  nu.x = 24.0f * 24.0f;  // the horizontal sigma is sqrt(var_x + var_y): 24.2 m
  nu.y = 10.0f;
  rig.vehicle.send(nu);
  EXPECT_FALSE(rig.ask("position_uncertain"));
  nu.x = 18.0f * 18.0f;  // 18 and 18: 25.5 m, over the limit though neither axis is
  nu.y = 18.0f * 18.0f;
  rig.vehicle.send(nu);
  EXPECT_TRUE(rig.ask("position_uncertain"));
}

// Issue 37's primitives over IMC.
TEST(ImcLink, RowsAreKeptByTheLinkAndEachNextRowIsAReferenceAtTheRowsEnd) {
  ImcRig rig;
  rig.connect();
  EXPECT_FALSE(rig.ask("rows_done"));  // no pattern
  auto none = rig.call(protocol::make_exec(0, "next_row"));
  ASSERT_TRUE(none.ok());
  auto* err = std::get_if<protocol::Err>(&none.value());
  ASSERT_NE(err, nullptr) << "refused as the Phoenix refuses it: err failed";
  EXPECT_EQ(err->code, protocol::ErrorCode::Failed);
  EXPECT_EQ(err->message, "next_row: no row pattern (start_rows first)");
  using protocol::Value;
  EXPECT_TRUE(rig.exec("start_rows", {Value::integer(0), Value::integer(0), Value::integer(0), Value::integer(100),
                                      Value::integer(20), Value::integer(2)}));
  EXPECT_FALSE(rig.ask("rows_done"));
  // Row 0 runs north from the origin: its end is 100 m north.
  imc::Reference ref = steered(rig, "next_row");
  EXPECT_NEAR(ref.lat, 0.7188 + 100.0 / 6378137.0, 1e-9);
  EXPECT_NEAR(ref.lon, -0.1519, 1e-12);
  EXPECT_FALSE(rig.ask("rows_done"));
  // Row 1 runs back south, 20 m to starboard (east): its end is 20 m east of the origin.
  ref = steered(rig, "next_row");
  EXPECT_NEAR(ref.lat, 0.7188, 1e-9);
  EXPECT_NEAR(ref.lon, -0.1519 + 20.0 / (6378137.0 * std::cos(0.7188)), 1e-12);
  EXPECT_TRUE(rig.ask("rows_done"));
  EXPECT_FALSE(rig.ask("waypoint_reached"));
  rig.vehicle.follow_state(imc::FollowRefState::kStateLoiter,
                           imc::FollowRefState::kProxXyNear | imc::FollowRefState::kProxZNear);
  EXPECT_TRUE(rig.ask("waypoint_reached"));
  auto past = rig.call(protocol::make_exec(0, "next_row"));
  ASSERT_TRUE(past.ok());
  err = std::get_if<protocol::Err>(&past.value());
  ASSERT_NE(err, nullptr);
  EXPECT_EQ(err->message, "next_row: no row left (all 2 rows started)");
  // A bad pattern is a failed exec, with the reason as an event.
  EXPECT_FALSE(rig.exec("start_rows", {Value::integer(0), Value::integer(0), Value::integer(0), Value::integer(100),
                                       Value::integer(20), Value::real(0.5)}));
  EXPECT_EQ(rig.events.back(), "exec start_rows failed: row count 0.5 is not a whole number from 1 to 1000");
}

TEST(ImcLink, SetSpeedIsTheCruiseSpeedOfTheNextGoalAndStopKeepsIt) {
  ImcRig rig;
  rig.connect();
  const std::size_t before = rig.vehicle.references.size();
  EXPECT_TRUE(rig.exec("set_speed", {protocol::Value::real(0.5)}));
  for (int i = 0; i < 3; ++i) rig.vehicle.state();
  settle(rig);
  // No goal: nothing steers, and any Reference of the stream says speed 0.
  for (std::size_t i = before; i < rig.vehicle.references.size(); ++i) {
    ASSERT_TRUE(rig.vehicle.references[i].speed);
    EXPECT_EQ(rig.vehicle.references[i].speed->value, 0.0);
  }
  imc::Reference ref = steered(rig, "goto_xy", {protocol::Value::integer(0), protocol::Value::integer(100)});
  ASSERT_TRUE(ref.speed);
  EXPECT_EQ(ref.speed->value, 0.5);
  ref = steered(rig, "set_speed", {protocol::Value::real(0.7)});  // a goal held: at once
  EXPECT_FLOAT_EQ(static_cast<float>(ref.speed->value), 0.7f);
  ref = steered(rig, "stop");
  EXPECT_EQ(ref.speed->value, 0.0);
  ref = steered(rig, "goto_xy", {protocol::Value::integer(0), protocol::Value::integer(200)});
  EXPECT_FLOAT_EQ(static_cast<float>(ref.speed->value), 0.7f);  // kept through stop
}

TEST(ImcLink, HoldPositionIsAReferenceWhereTheVehicleIs) {
  ImcRig rig;
  rig.connect();
  rig.vehicle.north_m = 30;
  rig.vehicle.east_m = 40;
  rig.vehicle.state();
  settle(rig);
  const imc::Reference ref = steered(rig, "hold_position");
  EXPECT_NEAR(ref.lat, 0.7188 + 30.0 / 6378137.0, 1e-9);
  EXPECT_NEAR(ref.lon, -0.1519 + 40.0 / (6378137.0 * std::cos(0.7188)), 1e-12);
  ASSERT_TRUE(ref.speed);
  EXPECT_FLOAT_EQ(static_cast<float>(ref.speed->value), 0.8f);  // the cruise speed, to come back
  rig.vehicle.follow_state(imc::FollowRefState::kStateLoiter,
                           imc::FollowRefState::kProxXyNear | imc::FollowRefState::kProxZNear);
  EXPECT_TRUE(rig.ask("waypoint_reached"));
}

TEST(ImcLink, SetTimerRunsOnTheVehiclesClock) {
  ImcRig rig;
  rig.connect();
  EXPECT_TRUE(rig.exec("set_timer", {protocol::Value::integer(2)}));
  EXPECT_FALSE(rig.ask("time_out"));
  for (int i = 0; i < 20; ++i) rig.vehicle.state();
  settle(rig);
  EXPECT_TRUE(rig.ask("time_out"));
  EXPECT_FALSE(rig.exec("set_timer", {protocol::Value::integer(0)}));
}

TEST(ImcLink, GpsAvailableIsAFreshValidFixAtTheSurface) {
  ImcRig rig;
  rig.connect();
  EXPECT_FALSE(rig.ask("gps_available"));  // no GpsFix heard
  imc::GpsFix fix;
  fix.validity = 0x1FF;
  fix.satellites = 9;
  rig.vehicle.send(fix);
  settle(rig);
  EXPECT_TRUE(rig.ask("gps_available"));
  for (int i = 0; i < 20; ++i) rig.vehicle.state();  // 2 s without one: stale
  settle(rig);
  EXPECT_FALSE(rig.ask("gps_available"));
  rig.vehicle.send(fix);
  rig.vehicle.depth_m = 2.0;  // under water
  rig.vehicle.state();
  settle(rig);
  EXPECT_FALSE(rig.ask("gps_available"));
  rig.vehicle.depth_m = 0.0;
  fix.validity = 0;  // no fix (DUNE: no satellites)
  fix.satellites = 0;
  rig.vehicle.state();
  rig.vehicle.send(fix);
  settle(rig);
  EXPECT_FALSE(rig.ask("gps_available"));
}

TEST(ImcLink, LoiterIsRefusedNotSent) {
  ImcRig rig;
  rig.connect();
  auto r = rig.call(protocol::make_exec(
      0, "loiter", {protocol::Value::integer(0), protocol::Value::integer(0), protocol::Value::integer(20)}));
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "an IMC vehicle has no 'loiter' (docs/imc.md)");
}

TEST(ExecutionLevel, AnImcVehicleRefusesWhatItHasNoCounterpartForAndCarriesTheRest) {
  const Catalogue& c = Catalogue::builtin();
  for (const char* refused : {"target_detected", "set_sway", "loiter"}) {
    ASSERT_NE(c.find(refused), nullptr) << refused;
    EXPECT_TRUE(unavailable_on(ExecutionLevel::Imc, *c.find(refused))) << refused;
    EXPECT_FALSE(unavailable_on(ExecutionLevel::Phoenix, *c.find(refused))) << refused;
  }
  std::size_t carried = 0;
  for (const Primitive& p : c.all()) carried += unavailable_on(ExecutionLevel::Imc, p) ? 0 : 1;
  EXPECT_EQ(carried, c.all().size() - 3);
  EXPECT_NE(unavailable_on(ExecutionLevel::Imc, *c.find("loiter"))->find("FollowReference"), std::string::npos);
  EXPECT_EQ(execution_level_of("imc://127.0.0.1:6002"), ExecutionLevel::Imc);
  EXPECT_EQ(execution_level_of("127.0.0.1:7020"), ExecutionLevel::Phoenix);
}

}  // namespace
}  // namespace strata::tactical::imc_link_tests
