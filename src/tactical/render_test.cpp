#include "tactical/render.h"

#include <gtest/gtest.h>

#include <cmath>

namespace strata::tactical {
namespace {

const std::string kRenderSourceDir = STRATA_SOURCE_DIR;

const Primitive& builtin(std::string_view name) {
  const Primitive* p = Catalogue::builtin().find(name);
  EXPECT_TRUE(p) << name;
  return *p;
}

std::string text_of(std::string_view name, std::vector<Value> args = {}) {
  auto r = render(builtin(name), args, nullptr);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
  return r.ok() ? r.value().text() : "";
}

std::string error_of(std::string_view name, std::vector<Value> args) {
  auto r = render(builtin(name), args, nullptr);
  EXPECT_FALSE(r.ok());
  return r.ok() ? "" : r.error().message;
}

MissionData tank_data() {
  auto d = MissionData::load(kRenderSourceDir + "/missions/tank/setpoints.toml");
  EXPECT_TRUE(d.ok()) << (d.ok() ? "" : d.error().message);
  return std::move(d).value();
}

TEST(Render, FillsTheTemplates) {
  EXPECT_EQ("exec submerge", text_of("submerge"));
  EXPECT_EQ("exec start_depth_filter", text_of("start_depth_filter"));
  EXPECT_EQ("ask depth_reached", text_of("depth_reached"));
  EXPECT_EQ("ood shutdown_network", text_of("shutdown_network"));
  EXPECT_EQ("exec sleep 1", text_of("sleep", {Value::of(1.0)}));
  EXPECT_EQ("exec sleep 0.5", text_of("sleep", {Value::of(0.5)}));
  EXPECT_EQ("exec sleep 3600", text_of("sleep", {Value::of(3600.0)}));
}

TEST(Render, SeparatesTheFieldsForTheProtocol) {
  std::vector<Value> args = {Value::of(2.5)};
  auto r = render(builtin("sleep"), args, nullptr);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(core::CallVerb::Exec, r.value().verb);
  EXPECT_EQ("sleep", r.value().name);
  EXPECT_EQ((std::vector<Value>{Value::of(2.5)}), r.value().args);
  EXPECT_TRUE(r.value().to_vehicle());
  // The reply timeout grows with the sleep.
  EXPECT_EQ(4.5, r.value().timeout_s);
  auto ask = render(builtin("time_out"), {}, nullptr);
  ASSERT_TRUE(ask.ok());
  EXPECT_EQ(2.0, ask.value().timeout_s);
  EXPECT_TRUE(ask.value().args.empty());
}

TEST(Render, RejectsBadArguments) {
  EXPECT_EQ("'sleep' takes 1 argument (seconds), but 0 given", error_of("sleep", {}));
  EXPECT_EQ("'sleep' takes 1 argument (seconds), but 2 given", error_of("sleep", {Value::of(1.0), Value::of(2.0)}));
  EXPECT_EQ("'submerge' takes no arguments, but 1 given", error_of("submerge", {Value::of(1.0)}));
  EXPECT_EQ("'sleep' argument 'seconds' must be a number, not the string \"soon\"",
            error_of("sleep", {Value::of("soon")}));
  EXPECT_EQ("'sleep' argument 'seconds' is 0 s, below the minimum 0.1 s", error_of("sleep", {Value::of(0.0)}));
  EXPECT_EQ("'sleep' argument 'seconds' is 4000 s, above the maximum 3600 s", error_of("sleep", {Value::of(4000.0)}));
  EXPECT_EQ("'sleep' argument 'seconds' must be a finite number", error_of("sleep", {Value::of(std::nan(""))}));
  EXPECT_EQ("'report' argument 'text' must be a string, not the number 3", error_of("report", {Value::of(3.0)}));
}

TEST(Render, ReportSendsNothing) {
  std::vector<Value> args = {Value::of("phase 1: system problem at start-up")};
  auto r = render(builtin("report"), args, nullptr);
  ASSERT_TRUE(r.ok());
  EXPECT_FALSE(r.value().to_vehicle());
  EXPECT_EQ("phase 1: system problem at start-up", r.value().text());
}

TEST(Render, NextSetpointDataReadsTheCursor) {
  MissionData data = tank_data();
  DataCursor cursor(data);
  const Primitive& p = builtin("next_setpt_data");
  // Nothing read yet: render alone cannot serve it.
  auto early = render(p, {}, &cursor);
  ASSERT_FALSE(early.ok());
  EXPECT_EQ("'next_setpt_data' reads the mission data, but no setpoint has been read", early.error().message);
  EXPECT_FALSE(render(p, {}, nullptr).ok());

  std::vector<std::string> sent;
  for (int i = 0; i < 3; ++i) {
    auto r = advance_and_render(p, {}, cursor);
    ASSERT_TRUE(r.ok()) << r.error().message;
    sent.push_back(r.value().text());
    EXPECT_EQ("setpoint", r.value().name);
    ASSERT_EQ(2u, r.value().args.size());
    EXPECT_EQ(Value::Type::Number, r.value().args[0].type);
  }
  EXPECT_EQ((std::vector<std::string>{"exec setpoint 0.6 30", "exec setpoint 1.5 45", "exec setpoint 0 60"}), sent);
  auto past = advance_and_render(p, {}, cursor);
  ASSERT_FALSE(past.ok());
  EXPECT_EQ("mission data has 3 setpoints; next_setpt_data was called a 4th time", past.error().message);
}

TEST(Render, ABadCallConsumesNoSetpoint) {
  MissionData data = tank_data();
  DataCursor cursor(data);
  std::vector<Value> extra = {Value::of(1.0)};
  EXPECT_FALSE(advance_and_render(builtin("next_setpt_data"), extra, cursor).ok());
  EXPECT_EQ(0u, cursor.position());
  // Primitives that read no data leave the cursor alone.
  EXPECT_TRUE(advance_and_render(builtin("submerge"), {}, cursor).ok());
  EXPECT_EQ(0u, cursor.position());
}

TEST(Render, StringArgumentsAndDefaults) {
  auto c = Catalogue::parse(
      "[[primitive]]\nname = \"light\"\nkind = \"exec\"\ndoc = \"d\"\ntimeout_s = 1\n"
      "message = \"exec light mode={mode} {level}\"\n"
      "args = [{ name = \"mode\", type = \"string\" },\n"
      "        { name = \"level\", type = \"number\", unit = \"\", min = 0, max = 1, default = 1 }]\n",
      "cat.toml");
  ASSERT_TRUE(c.ok()) << c.error().message;
  const Primitive& p = *c.value().find("light");
  std::vector<Value> one = {Value::of("strobe")};
  auto r = render(p, one, nullptr);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ("exec light mode=strobe 1", r.value().text());
  EXPECT_EQ((std::vector<Value>{Value::of("mode=strobe"), Value::of(1.0)}), r.value().args);
  std::vector<Value> two = {Value::of("dim"), Value::of(0.25)};
  EXPECT_EQ("exec light mode=dim 0.25", render(p, two, nullptr).value().text());
  std::vector<Value> spaced = {Value::of("two words")};
  auto bad = render(p, spaced, nullptr);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(
      "'light' argument 'mode' must be one word (no spaces or control characters) to go into "
      "the message, not \"two words\"",
      bad.error().message);
  std::vector<Value> empty = {Value::of("")};
  EXPECT_FALSE(render(p, empty, nullptr).ok());
}

TEST(Render, TheOpenWaterPrimitives) {
  EXPECT_EQ("exec goto_depth 2.5", text_of("goto_depth", {Value::of(2.5)}));
  EXPECT_EQ("exec track 0 0 200 -50.5",
            text_of("track", {Value::of(0.0), Value::of(0.0), Value::of(200.0), Value::of(-50.5)}));
  EXPECT_EQ("ask position_uncertain", text_of("position_uncertain"));
  EXPECT_NE(std::string::npos, error_of("set_speed", {Value::of(3.0)}).find("3"));
  EXPECT_FALSE(error_of("goto_xy", {Value::of(std::nan("")), Value::of(0.0)}).empty());
}

TEST(Render, NextWaypointReadsTheWaypointCursor) {
  auto d = MissionData::parse("[[waypoint]]\nx_m = 10\ny_m = -20\n", "data.toml");
  ASSERT_TRUE(d.ok()) << d.error().message;
  DataCursor cursor(d.value());
  const Primitive& p = builtin("next_waypoint");
  EXPECT_EQ(DataSource::Waypoint, p.data);
  EXPECT_FALSE(render(p, {}, &cursor).ok());  // none read yet
  auto r = advance_and_render(p, {}, cursor);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ("exec goto_xy 10 -20", r.value().text());
  EXPECT_FALSE(advance_and_render(p, {}, cursor).ok());
}

TEST(Value, NumbersUseTheShortestRoundTripForm) {
  EXPECT_EQ("1", to_string(Value::of(1.0)));
  EXPECT_EQ("0.1", to_string(Value::of(0.1)));
  EXPECT_EQ("0", to_string(Value::of(-0.0)));
  EXPECT_EQ("-2.5", to_string(Value::of(-2.5)));
  EXPECT_EQ("1e-07", to_string(Value::of(1e-7)));
}

}  // namespace
}  // namespace strata::tactical
