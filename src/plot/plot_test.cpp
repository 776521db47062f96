#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <pugixml.hpp>

#include "plot/gnuplot.h"
#include "plot/plot_log.h"
#include "core/test_fifo.h"
#include "plot/plot_test_support.h"

namespace strata::plot {
namespace {

namespace fs = std::filesystem;
using namespace testing;

std::string dump(const std::vector<PhaseBand>& phases) {
  std::string out;
  for (const auto& b : phases) {
    out += fmt::format("{}{}@{} {}-{} {}\n", std::string(static_cast<std::size_t>(b.depth - 1) * 2, ' '), b.net,
                       b.instance, b.start_s, b.end_s, b.ended ? b.result : "running");
  }
  return out;
}

std::string dump(const std::vector<AbortMark>& marks) {
  std::string out;
  for (const auto& m : marks) out += fmt::format("{} {}{}\n", m.time_s, m.label, m.mission ? " [mission]" : "");
  return out;
}

// PATH replaced for one test, then put back.
class ScopedPath {
 public:
  explicit ScopedPath(const std::string& value) : old_(std::getenv("PATH") ? std::getenv("PATH") : "") {
    setenv("PATH", value.c_str(), 1);
  }
  ~ScopedPath() { setenv("PATH", old_.c_str(), 1); }

 private:
  std::string old_;
};

void write_script(const fs::path& file, const std::string& body) {
  std::ofstream(file) << "#!/bin/sh\n" << body;
  fs::permissions(file, fs::perms::owner_all);
}

TEST(ReadLog, KnownLogGivesPhasesAbortsAndSeries) {
  const MissionPlot p = read_fixture("leak_phase2.jsonl");
  EXPECT_EQ(
      "initialize@1 0-0.2 completed\n"
      "dive_from_surface@2 0.2-7.8 aborted\n",
      dump(p.phases));
  EXPECT_EQ(
      "7.8 dive_from_surface aborted (exit abort)\n"
      "7.9 mission aborted (exit closed_after_abort) [mission]\n",
      dump(p.aborts));
  EXPECT_EQ(15u, p.depth_m.size());
  EXPECT_EQ(15u, p.filtered_depth_m.size());
  EXPECT_EQ(12u, p.setpoint_m.size());  // from 2 s on, once the dive is commanded
  EXPECT_EQ(2.0, p.setpoint_m.time_s.front());
  EXPECT_TRUE(p.heading_deg.empty());
  EXPECT_EQ(0.0, p.first_s);
  EXPECT_EQ(7.9, p.last_s);
  EXPECT_EQ("missions/tank/tank.coral, scenario leak_phase2: aborted (exit closed_after_abort)", p.title());
}

TEST(ReadLog, HeadingSetpointAndNestedPhases) {
  const MissionPlot p = read_fixture("heading.jsonl");
  EXPECT_EQ(
      "descend@1 0-2.5 completed\n"
      "turn_leg@2 2.5-5.5 aborted\n"
      "  hold_heading@3 3-4.5 aborted\n",
      dump(p.phases));
  EXPECT_EQ(
      "4.5 hold_heading aborted (exit drifted)\n"
      "5.5 turn_leg aborted (exit abort)\n"
      "6 mission aborted (exit closed_after_abort): compass drift [mission]\n",
      dump(p.aborts));
  EXPECT_EQ(6u, p.depth_m.size());
  EXPECT_EQ(5u, p.setpoint_m.size());
  EXPECT_EQ(6u, p.heading_deg.size());
  EXPECT_EQ(20.0, p.heading_deg.value.back());
}

TEST(ReadLog, CompletedMissionHasNoMarks) {
  auto r = read_text(R"({"event":"phase_start","instance":1,"net":"a","depth":1,"sim_time":0}
{"event":"telemetry","sim_time":0.5,"depth_m":0.1}

{"event":"phase_end","instance":1,"net":"a","exit":"done","result":"completed","sim_time":1}
{"event":"mission_end","outcome":"completed","exit":"closed","reason":"","sim_time":1}
)");
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ("a@1 0-1 completed\n", dump(r.value().phases));
  EXPECT_EQ("", dump(r.value().aborts));
  EXPECT_EQ("mission log: completed (exit closed)", r.value().title());
}

TEST(ReadLog, PhaseStillRunningEndsAtTheLogsEnd) {
  auto r = read_text(R"({"event":"phase_start","instance":4,"net":"dive","depth":1,"sim_time":1}
{"event":"telemetry","sim_time":3.5,"depth_m":0.4}
)");
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ("dive@4 1-3.5 running\n", dump(r.value().phases));
  EXPECT_EQ("", dump(r.value().aborts));
  EXPECT_EQ("mission log: the log ends before the mission did", r.value().title());
}

TEST(ReadLog, MalformedLineIsAnErrorNamingItsLine) {
  auto r = read_log_file(fixture("malformed.jsonl"));
  ASSERT_FALSE(r);
  EXPECT_EQ(core::ErrorCode::InvalidInput, r.error().code);
  EXPECT_EQ(fixture("malformed.jsonl") + ":3: not JSON (column 50)", r.error().message);
}

TEST(ReadLog, FieldOfTheWrongTypeNamesItsLine) {
  auto r = read_text(
      "{\"event\":\"telemetry\",\"sim_time\":0.5,\"depth_m\":0.1}\n"
      "{\"event\":\"telemetry\",\"sim_time\":1,\"depth_m\":\"deep\"}\n");
  ASSERT_FALSE(r);
  EXPECT_EQ("x.jsonl:2: telemetry: 'depth_m' is not a number", r.error().message);
}

TEST(ReadLog, LineThatIsNotAnObjectOrHasNoEvent) {
  auto array = read_text("[1, 2]\n");
  ASSERT_FALSE(array);
  EXPECT_EQ("x.jsonl:1: not a JSON object", array.error().message);
  auto nameless = read_text("\n{\"sim_time\":1}\n");
  ASSERT_FALSE(nameless);
  EXPECT_EQ("x.jsonl:2: no \"event\" name", nameless.error().message);
  auto timeless = read_text("{\"event\":\"phase_end\",\"instance\":1}\n");
  ASSERT_FALSE(timeless);
  EXPECT_EQ("x.jsonl:1: phase_end: no 'sim_time'", timeless.error().message);
}

TEST(ReadLog, NoTelemetryIsAnError) {
  auto r = read_log_file(fixture("no_telemetry.jsonl"));
  ASSERT_FALSE(r);
  EXPECT_EQ(core::ErrorCode::InvalidInput, r.error().code);
  EXPECT_EQ(fixture("no_telemetry.jsonl") + ": no telemetry with depth_m: nothing to plot", r.error().message);
}

TEST(ReadLog, MissingFileIsAnIoError) {
  auto r = read_log_file(fixture("no_such_log.jsonl"));
  ASSERT_FALSE(r);
  EXPECT_EQ(core::ErrorCode::Io, r.error().code);
  auto folder = read_log_file(fixture(""));
  ASSERT_FALSE(folder);
  EXPECT_EQ(core::ErrorCode::Io, folder.error().code);
}

TEST(Script, DepthAxisIsReversedAndNamesAreQuoted) {
  MissionPlot p = read_fixture("leak_phase2.jsonl");
  p.phases[0].net = "it's";
  const std::string s = gnuplot_script(p, Format::Svg, "/d", "/d/plot.svg");
  // The deeper end first: gnuplot puts it at the bottom.
  EXPECT_NE(std::string::npos, s.find("set yrange [0.65:-0.0855]")) << s;
  EXPECT_NE(std::string::npos, s.find("set label 'it''s' at first 0, ")) << s;
  EXPECT_NE(std::string::npos, s.find("set terminal svg ")) << s;
  EXPECT_EQ(std::string::npos, s.find("heading")) << s;
  EXPECT_NE(std::string::npos, gnuplot_script(p, Format::Png, "/d", "/d/plot.png").find("set terminal png "));
}

// A log's net name with a newline in it ended gnuplot's `set label` line,
// and the next line of the name ran as a command (`print system(...)`):
// `strata plot` of a log someone else wrote ran their commands.
TEST(Script, ANewlineInALogsTextCannotEndItsCommand) {
  MissionPlot p = read_fixture("leak_phase2.jsonl");
  p.phases[0].net = std::string("x\nprint system(\"touch /tmp/pwned\")\r\n#\0", 38);
  p.mission = "m\nquit";
  const std::string s = gnuplot_script(p, Format::Svg, "/d", "/d/plot.svg");
  EXPECT_NE(std::string::npos, s.find("set label 'x print system(\"touch /tmp/pwned\")  #")) << s;
  std::istringstream lines(s);
  for (std::string line; std::getline(lines, line);) {
    EXPECT_NE(0u, line.rfind("print", 0)) << line;
    EXPECT_NE(0u, line.rfind("quit", 0)) << line;
    EXPECT_EQ(std::string::npos, line.find('\r')) << line;
  }
}

TEST(Script, HeadingBreaksWhereItCrossesNorth) {
  TempDir dir;
  ASSERT_TRUE(write_data(read_fixture("heading.jsonl"), dir.path()));
  std::ifstream in(dir.path() / "heading.dat");
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ("0 340\n1 350\n2 355\n\n3 5\n4 15\n5 20\n", text.str());
  EXPECT_TRUE(fs::exists(dir.path() / "setpoint.dat"));
}

TEST(Render, FormatFromTheFileName) {
  EXPECT_EQ(Format::Svg, format_for("a/run.svg"));
  EXPECT_EQ(Format::Png, format_for("RUN.PNG"));
  EXPECT_FALSE(format_for("run.pdf"));
  EXPECT_FALSE(format_for("run"));
}

TEST(Render, GnuplotMissingSaysSo) {
  TempDir empty;
  ScopedPath path(empty.path().string());
  Rendered r = render(read_fixture("leak_phase2.jsonl"), {Format::Svg, empty.path() / "out.svg"});
  EXPECT_EQ(RenderStatus::GnuplotMissing, r.status);
  EXPECT_EQ("gnuplot not found: install gnuplot-nox", r.message);
  EXPECT_FALSE(fs::exists(empty.path() / "out.svg"));
}

TEST(Render, GnuplotFailingGivesItsStderr) {
  TempDir bin;
  write_script(bin.path() / "gnuplot", "echo \"plot.gp line 7: undefined variable: x\" >&2\nexit 1\n");
  ScopedPath path(bin.path().string());
  Rendered r = render(read_fixture("leak_phase2.jsonl"), {Format::Svg, bin.path() / "out.svg"});
  EXPECT_EQ(RenderStatus::GnuplotFailed, r.status);
  EXPECT_EQ("gnuplot exited with status 1:\nplot.gp line 7: undefined variable: x", r.message);
  EXPECT_FALSE(fs::exists(bin.path() / "out.svg"));
}

TEST(Render, GnuplotThatHangsIsStopped) {
  TempDir bin;
  write_script(bin.path() / "gnuplot", "exec sleep 30\n");
  ScopedPath path(bin.path().string() + ":/usr/bin:/bin");
  RenderOptions o{Format::Svg, bin.path() / "out.svg"};
  o.bound = std::chrono::milliseconds(300);
  Rendered r = render(read_fixture("leak_phase2.jsonl"), o);
  EXPECT_EQ(RenderStatus::GnuplotFailed, r.status);
  EXPECT_EQ("gnuplot was still running after 300 ms and was stopped", r.message);
}

TEST(Svg, KnownLogShowsItsPhasesAbortsAndDepthCurve) {
  SKIP_WITHOUT_GNUPLOT();
  TempDir dir;
  Svg svg;
  ASSERT_TRUE(draw("leak_phase2.jsonl", svg, dir));
  EXPECT_TRUE(svg.has_text("initialize"));
  EXPECT_TRUE(svg.has_text("dive_from_surface"));
  EXPECT_TRUE(svg.has_text("dive_from_surface aborted (exit abort)"));
  EXPECT_TRUE(svg.has_text("mission aborted (exit closed_after_abort)"));
  EXPECT_TRUE(svg.has_text("missions/tank/tank.coral, scenario leak_phase2: aborted (exit closed_after_abort)"));
  EXPECT_TRUE(svg.has_text("depth (m)"));
  EXPECT_FALSE(svg.has_text("heading (deg)"));

  // The key's sample line, then the curve through all 15 samples.
  const auto depth = svg.curve("depth");
  ASSERT_EQ(2u, depth.size());
  ASSERT_EQ(15u, depth[1].size());
  // Positive down: the deepest sample (index 12, 0.3286 m) is drawn below
  // the shallowest (index 2, -0.0355 m); SVG's y grows downwards.
  EXPECT_GT(depth[1][12].second, depth[1][2].second);
  EXPECT_EQ(2u, svg.curve("filtered depth").size());
  // The setpoint starts with the dive, at the fourth sample's time.
  const auto setpoint = svg.curve("setpoint");
  ASSERT_EQ(2u, setpoint.size());
  EXPECT_NEAR(depth[1][3].first, setpoint[1].front().first, 0.5);
}

TEST(Svg, HeadingGetsItsOwnPanel) {
  SKIP_WITHOUT_GNUPLOT();
  TempDir dir;
  Svg svg;
  ASSERT_TRUE(draw("heading.jsonl", svg, dir));
  EXPECT_TRUE(svg.has_text("descend"));
  EXPECT_TRUE(svg.has_text("turn_leg"));
  EXPECT_FALSE(svg.has_text("hold_heading"));  // nested: a strip, no label
  EXPECT_TRUE(svg.has_text("hold_heading aborted (exit drifted)"));
  EXPECT_TRUE(svg.has_text("mission aborted (exit closed_after_abort): compass drift"));
  EXPECT_TRUE(svg.has_text("heading (deg)"));
  // Lifted where it crosses north: the key's line, then 3 and 3 samples.
  const auto heading = svg.curve("heading");
  ASSERT_EQ(3u, heading.size());
  EXPECT_EQ(3u, heading[1].size());
  EXPECT_EQ(3u, heading[2].size());
  const auto depth = svg.curve("depth");
  ASSERT_EQ(2u, depth.size());
  EXPECT_EQ(6u, depth[1].size());
  // Both panels on one time axis: the first samples (t = 0) line up.
  EXPECT_NEAR(depth[1][0].first, heading[1][0].first, 0.5);
  // A step plot from t = 0 to t = 4: the change is a vertical segment.
  const auto setpoint = svg.curve("setpoint");
  ASSERT_EQ(2u, setpoint.size());
  EXPECT_NEAR(depth[1][0].first, setpoint[1].front().first, 0.5);
  EXPECT_NEAR(depth[1][4].first, setpoint[1].back().first, 0.5);
  int vertical = 0;
  for (std::size_t i = 1; i < setpoint[1].size(); ++i) {
    const auto [x0, y0] = setpoint[1][i - 1];
    const auto [x1, y1] = setpoint[1][i];
    if (std::abs(x1 - x0) < 0.01 && std::abs(y1 - y0) > 1.0) ++vertical;
  }
  EXPECT_EQ(1, vertical);
}

TEST(Png, IsAPngPicture) {
  SKIP_WITHOUT_GNUPLOT();
  TempDir dir;
  const fs::path out = dir.path() / "out.png";
  Rendered r = render(read_fixture("heading.jsonl"), {Format::Png, out});
  ASSERT_TRUE(r.ok()) << r.message;
  std::ifstream in(out, std::ios::binary);
  std::string magic(8, '\0');
  in.read(magic.data(), 8);
  EXPECT_EQ("\x89PNG\r\n\x1a\n", magic);
}

TEST(Render, KeepFolderLeavesTheScript) {
  SKIP_WITHOUT_GNUPLOT();
  TempDir dir;
  RenderOptions o{Format::Svg, dir.path() / "out.svg"};
  o.keep_folder = true;
  Rendered r = render(read_fixture("leak_phase2.jsonl"), o);
  ASSERT_TRUE(r.ok()) << r.message;
  ASSERT_FALSE(r.kept_folder.empty());
  EXPECT_TRUE(fs::exists(r.kept_folder / "plot.gp"));
  EXPECT_TRUE(fs::exists(r.kept_folder / "depth.dat"));
  fs::remove_all(r.kept_folder);
}

TEST(ReadLog, AFifoGivenAsTheLogIsAnErrorNotAHang) {
  const auto fifo = core::testing::make_fifo("mission.jsonl");
  ASSERT_FALSE(fifo.empty());
  auto r = read_log_file(fifo.string());
  std::filesystem::remove_all(fifo.parent_path());
  ASSERT_FALSE(r);
  EXPECT_EQ(core::ErrorCode::Io, r.error().code);
  EXPECT_NE(r.error().message.find("not a regular file"), std::string::npos) << r.error().message;
}

}  // namespace
}  // namespace strata::plot
