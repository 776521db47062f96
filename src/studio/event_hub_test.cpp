#include "studio/event_hub.h"

#include <gtest/gtest.h>

#include "protocol/message.h"
#include "studio/run_publisher.h"

namespace strata::studio {
namespace {

using namespace std::chrono_literals;

TEST(EventHub, ANewStreamStartsWithTheSnapshotThenGetsEventsInOrder) {
  EventHub hub;
  hub.publish("run_start", {{"run", 1}, {"mission", "tank.coral"}, {"nets", nlohmann::json::array()}});
  hub.publish("phase_start", {{"instance", 0}, {"net", "tank"}, {"marking", {{"begin", 1}}}});
  auto sub = hub.subscribe();
  hub.publish("fired", {{"instance", 0}, {"marking", {{"a", 1}}}});
  hub.publish("report", {{"t", 1.5}, {"text", "hello"}});
  auto text = sub->next(100ms);
  ASSERT_TRUE(text.has_value());
  const auto snap = text->find("event: snapshot\n");
  const auto fired = text->find("event: fired\n");
  const auto report = text->find("event: report\n");
  EXPECT_EQ(0u, snap);
  EXPECT_LT(snap, fired);
  EXPECT_LT(fired, report);
  EXPECT_NE(std::string::npos, text->find("\"marking\":{\"begin\":1}")) << *text;
}

TEST(EventHub, TheSnapshotFollowsTheRun) {
  EventHub hub;
  hub.publish("run_start", {{"run", 2}, {"mission", "m.coral"}});
  hub.publish("phase_start", {{"instance", 0}, {"net", "m"}, {"marking", {{"begin", 1}}}});
  hub.publish("phase_start", {{"instance", 1}, {"net", "p"}, {"marking", {{"start", 1}}}});
  hub.publish("fired", {{"instance", 1}, {"marking", {{"go", 1}}}, {"enabled", {"t"}}});
  hub.publish("action_start", {{"id", 7}, {"instance", 1}, {"primitive", "sleep"}});
  hub.publish("telemetry", {{"t", 0.5}, {"depth", 0.1}, {"setpoint", 1.0}});
  auto s = hub.snapshot();
  EXPECT_EQ(1u, s["in_flight"].size());
  hub.publish("action_finish", {{"id", 7}, {"instance", 1}});
  EXPECT_TRUE(hub.snapshot()["in_flight"].empty());
  hub.publish("phase_end", {{"instance", 1}, {"net", "p"}});
  s = hub.snapshot();
  EXPECT_EQ(2, s["run"]);
  ASSERT_EQ(1u, s["instances"].size());
  EXPECT_EQ("m", s["instances"][0]["net"]);
  EXPECT_EQ(nlohmann::json::array({0.5, 0.1, 1.0}), s["telemetry"][0]);
  // A sample with a position (open water) carries it at the end of its row.
  hub.publish("telemetry", {{"t", 0.6}, {"depth", 0.2}, {"setpoint", nullptr}, {"x", 12.5}, {"y", -3.0}});
  EXPECT_EQ(nlohmann::json::array({0.6, 0.2, nullptr, 12.5, -3.0}), hub.snapshot()["telemetry"][1]);
  hub.publish("run_end", {{"outcome", "completed"}});
  s = hub.snapshot();
  EXPECT_TRUE(s["in_flight"].empty());
  EXPECT_EQ("completed", s["ended"]["outcome"]);
}

// Issue 17: finished phases stayed "in flight" to the end of the run: the
// engine tells a phase's end, not an answer to the PHASE action.
TEST(EventHub, AFinishedPhaseIsNoLongerInFlightNorAnyActionOfItsNet) {
  EventHub hub;
  hub.publish("run_start", {{"run", 1}, {"mission", "m.coral"}});
  hub.publish("phase_start", {{"instance", 0}, {"net", "m"}, {"marking", {{"begin", 1}}}});
  hub.publish("action_start", {{"id", 3}, {"instance", 0}, {"kind", "phase"}, {"primitive", "p"}});
  hub.publish("phase_start", {{"instance", 1}, {"parent", 0}, {"net", "p"}, {"marking", {{"start", 1}}}});
  hub.publish("action_start", {{"id", 4}, {"instance", 1}, {"kind", "exec"}, {"primitive", "sleep"}});
  hub.publish("action_start", {{"id", 5}, {"instance", 0}, {"kind", "exec"}, {"primitive", "other"}});
  EXPECT_EQ(3u, hub.snapshot()["in_flight"].size());
  hub.publish("fired", {{"instance", 1}, {"marking", {{"done", 1}}}});
  hub.publish("phase_end", {{"instance", 1}, {"net", "p"}, {"exit", "done"}, {"action", 3}, {"cancelled", false}});
  auto s = hub.snapshot();
  ASSERT_EQ(1u, s["in_flight"].size()) << s["in_flight"].dump();
  EXPECT_EQ(5, s["in_flight"][0]["id"]);
  // The phase's last marking is kept as its net's final one.
  ASSERT_EQ(1u, s["final"].size());
  EXPECT_EQ("p", s["final"][0]["net"]);
  EXPECT_EQ(nlohmann::json({{"done", 1}}), s["final"][0]["marking"]);
  EXPECT_EQ("done", s["final"][0]["exit"]);
}

// Issue 17: final markings were lost on reload: the mission's instance left
// the snapshot with its phase_end.
TEST(EventHub, FinalMarkingsStayInTheSnapshotAfterTheRunUntilTheNextOne) {
  EventHub hub;
  hub.publish("run_start", {{"run", 1}, {"mission", "m.coral"}});
  hub.publish("phase_start", {{"instance", 0}, {"net", "m"}, {"marking", {{"begin", 1}}}});
  hub.publish("fired", {{"instance", 0}, {"marking", {{"closed", 1}}}});
  hub.publish("phase_end", {{"instance", 0}, {"net", "m"}, {"exit", "closed"}});
  hub.publish("run_end", {{"outcome", "completed"}});
  auto s = hub.snapshot();
  EXPECT_TRUE(s["instances"].empty());
  ASSERT_EQ(1u, s["final"].size());
  EXPECT_EQ(nlohmann::json({{"closed", 1}}), s["final"][0]["marking"]);
  // A page connecting now gets them in its first event.
  auto sub = hub.subscribe();
  auto text = sub->next(10ms);
  ASSERT_TRUE(text);
  EXPECT_NE(std::string::npos, text->find("\"final\":[{")) << *text;
  hub.publish("run_start", {{"run", 2}, {"mission", "m.coral"}});
  EXPECT_TRUE(hub.snapshot()["final"].empty());
}

TEST(EventHub, WhatEveryReaderHasTakenIsFreedByTheReaders) {
  EventHub hub;
  auto a = hub.subscribe();
  auto b = hub.subscribe();
  hub.publish("run_start", {{"run", 1}});
  hub.publish("phase_start", {{"instance", 0}, {"net", "m"}, {"marking", {{"a", 1}}}});
  for (int i = 1; i <= 5; ++i) hub.publish("fired", {{"instance", 0}, {"index", i}, {"marking", {{"a", i}}}});
  // 7 in the log, and the references the snapshot let go of as it moved on.
  EXPECT_GT(hub.kept(), 7u);
  ASSERT_TRUE(a->next(10ms).has_value());
  EXPECT_EQ(7u, hub.kept());  // b has not read the log yet
  auto text = b->next(10ms);
  ASSERT_TRUE(text.has_value());
  EXPECT_NE(std::string::npos, text->find("\"index\":5")) << *text;
  EXPECT_EQ(0u, hub.kept());
  // The snapshot still has the latest marking.
  EXPECT_EQ(5, hub.snapshot()["instances"][0]["marking"]["a"]);
}

TEST(EventHub, WithNobodyReadingNothingIsKept) {
  EventHub hub;
  hub.publish("run_start", {{"run", 1}});
  hub.publish("phase_start", {{"instance", 0}, {"net", "m"}, {"marking", {{"a", 1}}}});
  for (int i = 1; i <= 5; ++i) hub.publish("fired", {{"instance", 0}, {"index", i}});
  EXPECT_EQ(0u, hub.kept());
  auto a = hub.subscribe();
  a.reset();
  hub.publish("fired", {{"instance", 0}, {"index", 6}});
  EXPECT_EQ(0u, hub.kept());
}

TEST(EventHub, AReaderThatFallsBehindStartsAgainFromASnapshot) {
  EventHub hub(4);
  auto sub = hub.subscribe();
  hub.publish("run_start", {{"run", 1}});
  hub.publish("phase_start", {{"instance", 0}, {"net", "m"}, {"marking", {{"a", 1}}}});
  for (int i = 1; i <= 6; ++i) hub.publish("fired", {{"instance", 0}, {"index", i}, {"marking", {{"a", i}}}});
  EXPECT_EQ(9u, sub->behind());  // its first snapshot and 8 events
  auto text = sub->next(10ms);
  ASSERT_TRUE(text.has_value());
  // The first snapshot, then (the log keeps 4) a fresh one with the marking
  // of the last firing, and nothing older than what the log still had.
  EXPECT_EQ(0u, text->find("event: snapshot"));
  const auto second = text->find("event: snapshot", 1);
  ASSERT_NE(std::string::npos, second) << *text;
  EXPECT_NE(std::string::npos, text->find("\"marking\":{\"a\":6}", second));
  EXPECT_EQ(std::string::npos, text->find("\"index\":1"));
  EXPECT_EQ(0u, sub->behind());
}

TEST(EventHub, NobodyListeningKeepsOnlyTheSnapshot) {
  EventHub hub(4);
  for (int i = 0; i < 100; ++i) hub.publish("report", {{"text", "r"}});
  EXPECT_EQ(100u, hub.snapshot()["reports"].size());
  auto sub = hub.subscribe();
  auto text = sub->next(10ms);
  ASSERT_TRUE(text.has_value());
  EXPECT_EQ(0u, text->find("event: snapshot"));
  EXPECT_EQ(std::string::npos, text->find("event: report"));
}

TEST(EventHub, NothingNewIsAnEmptyChunkAndClosingEndsTheStream) {
  EventHub hub;
  auto sub = hub.subscribe();
  ASSERT_TRUE(sub->next(10ms).has_value());  // the snapshot
  EXPECT_EQ("", sub->next(10ms).value());
  hub.close();
  EXPECT_FALSE(sub->next(10ms).has_value());
  EXPECT_EQ(1u, hub.subscribers());
  sub.reset();
  EXPECT_EQ(0u, hub.subscribers());
}

}  // namespace
}  // namespace strata::studio

namespace strata::studio {
namespace {

// Issue 20: an open-water sample's estimated position (the line's x= and y=)
// goes to the live view's map; a tank sample has none, and its row stays
// [t, depth, setpoint]. A position that is not a number is left out.
TEST(RunPublisher, TelemetryCarriesThePositionOfAnOpenWaterSample) {
  EventHub hub;
  RunPublisher pub(hub);
  protocol::Telemetry tank;
  tank.sim_time_s = 1.0;
  tank.depth_m = 0.5;
  pub.telemetry(tank);
  protocol::Telemetry sea = tank;
  sea.sim_time_s = 2.0;
  sea.extras["x"] = "125.50";
  sea.extras["y"] = "-20.25";
  pub.telemetry(sea);
  protocol::Telemetry bad = sea;
  bad.sim_time_s = 3.0;
  bad.extras["y"] = "nan";
  pub.telemetry(bad);
  const auto rows = hub.snapshot()["telemetry"];
  ASSERT_EQ(3u, rows.size()) << rows.dump();
  EXPECT_EQ(nlohmann::json::array({1.0, 0.5, nullptr}), rows[0]);
  EXPECT_EQ(nlohmann::json::array({2.0, 0.5, nullptr, 125.5, -20.25}), rows[1]);
  EXPECT_EQ(3u, rows[2].size()) << rows[2].dump();
}

}  // namespace
}  // namespace strata::studio
