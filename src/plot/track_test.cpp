// The open-water plot: the track read from a log, its data files and script,
// hostile logs, and the picture gnuplot draws. The tank plot is pinned here
// too: a log without x/y telemetry gives the script it always gave.
#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "plot/gnuplot.h"
#include "plot/plot_log.h"
#include "plot/plot_test_support.h"
#include "plot/script_parts.h"

namespace strata::plot {
namespace {

using namespace testing;

std::string slurp(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string dump(const std::vector<PlannedLeg>& plan) {
  std::string out;
  for (const auto& l : plan) {
    out += fmt::format("{}@{} {} -> {},{}\n", l.track ? "track" : "goto_xy", l.time_s,
                       l.from_known ? fmt::format("{},{}", l.from.x_m, l.from.y_m) : "?", l.to.x_m, l.to.y_m);
  }
  return out;
}

std::string dump(const std::vector<Fix>& fixes) {
  std::string out;
  for (const auto& f : fixes) out += fmt::format("fix@{} {},{}\n", f.time_s, f.at.x_m, f.at.y_m);
  return out;
}

std::string lines(const std::vector<std::string>& notes) {
  std::string out;
  for (const auto& n : notes) out += n + "\n";
  return out;
}

// A telemetry line at `t` with the open-water fields.
std::string telemetry(double t, const std::string& xy) {
  return fmt::format("{{\"event\":\"telemetry\",\"sim_time\":{},\"depth_m\":1,\"altitude_m\":9,{}}}\n", t, xy);
}

TEST(ReadTrack, OpenWaterLogGivesTrackPlanAndFixes) {
  const MissionPlot p = read_fixture("open_water.jsonl");
  ASSERT_TRUE(p.has_track());
  EXPECT_EQ(37u, p.estimated.size());
  EXPECT_EQ(37u, p.truth.size());
  EXPECT_EQ(37u, p.altitude_m.size());
  EXPECT_EQ(37u, p.seabed_m.size());
  // The first line: depth -0.0345 m, altitude 19.99 m.
  EXPECT_NEAR(19.9555, p.seabed_m.value.front(), 1e-9);
  // The goto_xy starts where the estimate stood before its request (34.5 s).
  EXPECT_EQ(
      "track@0.3 0,0 -> 30,0\n"
      "goto_xy@35.7 26.24,0.05 -> 30,20\n",
      dump(p.plan));
  // The first gps_fix was answered 1 at 0.2 s and drawn at the next
  // estimate; the second, refused under water, is not drawn.
  EXPECT_EQ("fix@0.2 0.54,0.29\n", dump(p.fixes));
  EXPECT_EQ("", lines(p.notes));
}

TEST(ReadTrack, TankLogHasNoTrack) {
  for (const char* name : {"leak_phase2.jsonl", "heading.jsonl"}) {
    const MissionPlot p = read_fixture(name);
    EXPECT_FALSE(p.has_track()) << name;
    EXPECT_TRUE(p.altitude_m.empty() && p.plan.empty() && p.fixes.empty() && p.notes.empty()) << name;
  }
}

// The scripts of the tank fixtures as they were before the open-water plot
// (tests/plot/*.gp, written by `strata plot --keep-script`, folder as /d).
TEST(Script, TankScriptIsUnchanged) {
  for (const char* name : {"leak_phase2", "heading"}) {
    const MissionPlot p = read_fixture(fmt::format("{}.jsonl", name).c_str());
    EXPECT_EQ(slurp(fixture(fmt::format("{}.gp", name).c_str())), gnuplot_script(p, Format::Svg, "/d", "/d/plot.svg"))
        << name;
  }
}

TEST(Script, OpenWaterHasTheXyPanelAndItsData) {
  const MissionPlot p = read_fixture("open_water.jsonl");
  const std::string s = gnuplot_script(p, Format::Svg, "/d", "/d/plot.svg");
  for (const char* wanted :
       {"set size ratio -1 0.42,0.94\n", "set xlabel 'x east (m)'\n", "set ylabel 'y north (m)'\n",
        "'/d/track.dat' using 1:2 with lines lw 2 lc rgb '#0044aa' title 'estimated track'",
        "'/d/true_track.dat' using 1:2 ", "'/d/track_lines.dat' using 1:2 ", "'/d/goto_lines.dat' using 1:2 ",
        "'/d/waypoints.dat' using 1:2 with points", "'/d/fixes.dat' using 1:2 with points",
        "title 'seabed (depth + altitude)'", "set ylabel 'altitude (m)'\n", "set ylabel 'heading (deg)'\n",
        "set ylabel 'depth (m)'\n", "set size noratio\n"}) {
    EXPECT_NE(std::string::npos, s.find(wanted)) << wanted << "\n" << s;
  }
  // The mission's abort: its line ends over its number, at the bottom of
  // the depth panel, and its text is beside the key, in lines that fit the
  // right margin (track_layout_test.cpp checks where they land).
  for (const char* wanted :
       {"set arrow from first 61.4, graph 0.14064697609 to first 61.4, graph 1 nohead lc rgb '#cc0000' dt 1 ",
        "set label '1' at first 61.4, graph 0.0492264416315 center tc rgb '#cc0000' front\n",
        "set label '1' at graph 1, graph 1 left offset 1,-4 tc rgb '#cc0000' front\n",
        "set label 'mission failed: exec' at graph 1, graph 1 left offset 3,-4 ",
        "set label 'gps_fix was not executed:' at graph 1, graph 1 left offset 3,-5 ",
        "set label 'the vehicle answered 0 at' at graph 1, graph 1 left offset 3,-6 ",
        "set label '61.4 s' at graph 1, graph 1 left offset 3,-7 "}) {
    EXPECT_NE(std::string::npos, s.find(wanted)) << wanted << "\n" << s;
  }
  // The x-y panel comes first, before any time axis is set.
  EXPECT_LT(s.find("x east"), s.find("set xrange"));

  TempDir dir;
  ASSERT_TRUE(write_data(p, dir.path()));
  EXPECT_EQ("0 0\n30 0\n\n", slurp(dir.path() / "track_lines.dat"));
  EXPECT_EQ("26.24 0.05\n30 20\n\n", slurp(dir.path() / "goto_lines.dat"));
  EXPECT_EQ("30 0\n30 20\n", slurp(dir.path() / "waypoints.dat"));
  EXPECT_EQ("0.54 0.29\n", slurp(dir.path() / "fixes.dat"));
  EXPECT_EQ("0.54 0.29\n", slurp(dir.path() / "track.dat").substr(0, 10));
  EXPECT_EQ("0 0.05\n", slurp(dir.path() / "true_track.dat").substr(0, 7));
  EXPECT_EQ("0.5 19.99\n", slurp(dir.path() / "altitude.dat").substr(0, 10));
  EXPECT_TRUE(fs::exists(dir.path() / "depth.dat"));
}

TEST(Script, WrappedBreaksAtSpaces) {
  EXPECT_EQ((std::vector<std::string>{"ab cd", "efghijk", "l"}), script::wrapped("ab cd efghijk l", 5));
  EXPECT_EQ((std::vector<std::string>{"ab cd efghijk l"}), script::wrapped("ab  cd efghijk l", 0));
  EXPECT_EQ((std::vector<std::string>{""}), script::wrapped("", 5));
}

TEST(Script, WithoutPlansOrFixesTheirCurvesAreLeftOut) {
  auto r = read_text(telemetry(0, "\"x_m\":0,\"y_m\":0") + telemetry(1, "\"x_m\":5,\"y_m\":1"));
  ASSERT_TRUE(r) << r.error().message;
  const std::string s = gnuplot_script(r.value(), Format::Png, "/d", "/d/plot.png");
  EXPECT_NE(std::string::npos, s.find("'/d/track.dat'"));
  for (const char* absent : {"true_track.dat", "track_lines.dat", "goto_lines.dat", "waypoints", "fixes", "heading"}) {
    EXPECT_EQ(std::string::npos, s.find(absent)) << absent;
  }
}

TEST(ReadTrack, RefusedCallsAreNotDrawn) {
  auto r = read_text(telemetry(0, "\"x_m\":1,\"y_m\":2") +
                     R"({"event":"request","id":4,"message":"exec goto_xy 90 0","sim_time":0}
{"event":"reply","id":4,"result":0,"sim_time":0.1}
{"event":"request","id":6,"message":"exec gps_fix","sim_time":0.1}
{"event":"reply","id":6,"result":{"error":"no gps"},"sim_time":0.2}
{"event":"request","id":8,"message":"exec goto_xy 10 -5","sim_time":0.2}
)" + telemetry(0.5, "\"x_m\":3,\"y_m\":2") +
                     R"({"event":"reply","id":8,"result":1,"sim_time":0.6}
{"event":"request","id":10,"message":"exec gps_fix","sim_time":0.6}
{"event":"reply","id":10,"result":1,"sim_time":0.7}
)");
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ("goto_xy@0.2 1,2 -> 10,-5\n", dump(r.value().plan));
  // No telemetry after the fix: the last estimate before it.
  EXPECT_EQ("fix@0.7 3,2\n", dump(r.value().fixes));
}

TEST(ReadTrack, GotoBeforeAnyEstimateHasOnlyItsWaypoint) {
  auto r = read_text(R"({"event":"request","id":2,"message":"exec goto_xy 10 5","sim_time":0}
{"event":"reply","id":2,"result":1,"sim_time":0.1}
)" + telemetry(1, "\"x_m\":0,\"y_m\":0"));
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ("goto_xy@0 ? -> 10,5\n", dump(r.value().plan));
  TempDir dir;
  ASSERT_TRUE(write_data(r.value(), dir.path()));
  EXPECT_FALSE(fs::exists(dir.path() / "goto_lines.dat"));
  EXPECT_EQ("10 5\n", slurp(dir.path() / "waypoints.dat"));
}

TEST(ReadTrack, HugeOrOddValuesAreSkippedWithTheirLine) {
  auto r = read_text(telemetry(0, "\"x_m\":1,\"y_m\":2") + telemetry(1, "\"x_m\":1e300,\"y_m\":2") +
                     telemetry(2, "\"x_m\":3,\"true_x_m\":3,\"true_y_m\":-1e9") +
                     R"({"event":"request","id":2,"message":"exec track 0 0 nan 0","sim_time":3}
{"event":"request","id":3,"message":"exec track 0 0 5","sim_time":3}
{"event":"request","id":4,"message":"exec goto_xy 1e999 0","sim_time":3}
{"event":"reply","id":2,"result":1,"sim_time":3.1}
{"event":"reply","id":3,"result":1,"sim_time":3.1}
{"event":"reply","id":4,"result":1,"sim_time":3.1}
{"event":"telemetry","sim_time":4,"depth_m":1,"altitude_m":-1e20}
)");
  ASSERT_TRUE(r) << r.error().message;
  const MissionPlot& p = r.value();
  EXPECT_EQ(
      "x.jsonl:2: telemetry: x_m 1e+300 is beyond 1000 km: skipped\n"
      "x.jsonl:3: telemetry: x_m without y_m: skipped\n"
      "x.jsonl:3: telemetry: true_y_m -1000000000 is beyond 1000 km: skipped\n"
      "x.jsonl:4: request: 'exec track 0 0 nan 0': 'nan' is not a coordinate: skipped\n"
      "x.jsonl:5: request: 'exec track 0 0 5': track takes 4 numbers: skipped\n"
      "x.jsonl:6: request: 'exec goto_xy 1e999 0': '1e999' is not a coordinate: skipped\n"
      "x.jsonl:10: telemetry: altitude_m -1e+20 is beyond 1000 km: skipped\n",
      lines(p.notes));
  EXPECT_EQ(1u, p.estimated.size());
  EXPECT_TRUE(p.truth.empty());
  EXPECT_TRUE(p.plan.empty());
  EXPECT_EQ(3u, p.altitude_m.size());
  EXPECT_EQ(4u, p.depth_m.size());
}

TEST(ReadTrack, OtherRequestsAreNotCheckedButAGuidanceCallIs) {
  const std::string start = telemetry(0, "\"x_m\":0,\"y_m\":0");
  // As before the track was read: a request the plot does not draw, even
  // an odd one, is ignored.
  EXPECT_TRUE(read_text(start + "{\"event\":\"request\",\"message\":\"exec surface\"}\n"));
  EXPECT_TRUE(read_text(start + "{\"event\":\"request\",\"message\":7}\n{\"event\":\"reply\",\"id\":-1}\n"));
  auto no_id = read_text(start + "{\"event\":\"request\",\"message\":\"exec gps_fix\",\"sim_time\":1}\n");
  ASSERT_FALSE(no_id);
  EXPECT_EQ("x.jsonl:2: request: 'id' is missing or not a count", no_id.error().message);
  auto no_time = read_text(start + "{\"event\":\"request\",\"id\":3,\"message\":\"exec gps_fix\",\"sim_time\":1}\n" +
                           "{\"event\":\"reply\",\"id\":3,\"result\":1}\n");
  ASSERT_FALSE(no_time);
  EXPECT_EQ("x.jsonl:3: reply: no 'sim_time'", no_time.error().message);
}

TEST(ReadTrack, NotesStopAtTheirLimitAndAreCounted) {
  std::string log;
  for (int i = 0; i < 30; ++i) log += telemetry(i, "\"x_m\":1e7,\"y_m\":0");
  auto r = read_text(log);
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(kMaxNotes, r.value().notes.size());
  EXPECT_EQ(30 - kMaxNotes, r.value().skipped_notes);
  EXPECT_FALSE(r.value().has_track());
}

TEST(ReadTrack, NanOrACutLineIsAnErrorNamingItsLine) {
  auto nan = read_text(telemetry(0, "\"x_m\":1,\"y_m\":2") + "{\"event\":\"telemetry\",\"sim_time\":1,\"x_m\":NaN}\n");
  ASSERT_FALSE(nan);
  EXPECT_EQ("x.jsonl:2: not JSON (column 41)", nan.error().message);
  auto cut = read_text(telemetry(0, "\"x_m\":1,\"y_m\":2") + "{\"event\":\"telemetry\",\"sim_time\":1,\"x_m\":4");
  ASSERT_FALSE(cut);
  EXPECT_EQ("x.jsonl:2: not JSON (column 42)", cut.error().message);
  auto text = read_text(telemetry(0, "\"x_m\":\"east\",\"y_m\":2"));
  ASSERT_FALSE(text);
  EXPECT_EQ("x.jsonl:1: telemetry: 'x_m' is not a number", text.error().message);
}

TEST(Svg, OpenWaterDrawsTheTrackWithEqualScales) {
  SKIP_WITHOUT_GNUPLOT();
  TempDir dir;
  Svg svg;
  ASSERT_TRUE(draw("open_water.jsonl", svg, dir));
  for (const char* text : {"x east (m)", "y north (m)", "GPS fix", "waypoint", "true track", "depth (m)",
                           "altitude (m)", "heading (deg)", "seabed (depth + altitude)"}) {
    EXPECT_TRUE(svg.has_text(text)) << text;
  }
  // The key's sample line, then all 37 estimates in one stroke.
  const auto estimated = svg.curve("estimated track");
  ASSERT_EQ(2u, estimated.size());
  EXPECT_EQ(37u, estimated[1].size());
  // The track line (0,0)-(30,0) and the goto_xy line (26.24,0.05)-(30,20):
  // one metre is as many pixels east as north.
  const auto track = svg.curve("planned track");
  const auto go = svg.curve("planned goto_xy");
  ASSERT_EQ(2u, track.size());
  ASSERT_EQ(2u, go.size());
  ASSERT_EQ(2u, track[1].size());
  ASSERT_FALSE(go[1].empty());
  const double east_px_per_m = (track[1][1].first - track[1][0].first) / 30.0;
  const double north_px_per_m = (go[1].front().second - go[1].back().second) / (20 - 0.05);
  EXPECT_GT(east_px_per_m, 1.0);
  EXPECT_NEAR(east_px_per_m, north_px_per_m, 0.02 * east_px_per_m);
}

}  // namespace
}  // namespace strata::plot
