// The open-water plot's layout, read back from the script it writes: the
// x-y panel's box and ticks, and where the abort texts land in the depth
// panel. Sizes are measured the way gnuplot draws them (its PNG font: about
// 8.1 pixels a character across, 15 down), not taken from the code.
#include <cmath>
#include <regex>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "plot/gnuplot.h"
#include "plot/plot_test_support.h"
#include "plot/track_layout.h"

namespace strata::plot {
namespace {

using namespace testing;

constexpr double kCharW = 8.1;
constexpr double kCharH = 15.0;
constexpr double kPictureW = 1400;
constexpr double kPictureH = 800;

// A survey leg straight east, 250 m long and a metre or two wide, over a
// seabed rising from 30 m to 27 m; a nested phase, its leg and the mission
// abort within 15 s near the end of the run, as a leak does.
std::string survey_log() {
  std::string log = R"({"event":"run","mission":"survey.coral","scenario":"straight"}
{"event":"phase_start","instance":0,"net":"survey","depth":0,"sim_time":0}
{"event":"phase_start","instance":1,"net":"launch","depth":1,"sim_time":0}
)";
  for (int t = 0; t <= 620; ++t) {
    const double depth = t < 100 ? 0.0 : (t < 585 ? 5.0 : 5.0 * (620 - t) / 35.0);
    const double seabed = 30.0 - 3.0 * t / 620.0;
    log += fmt::format(
        R"({{"event":"telemetry","sim_time":{},"depth_m":{},"setpoint_m":{},"altitude_m":{},"x_m":{},"y_m":{},"heading_deg":90}})"
        "\n",
        t, depth, t < 100 || t >= 585 ? 0 : 5, seabed - depth, 250.0 * t / 620.0, 1.5 * std::sin(t / 80.0));
    if (t == 100) {
      log += R"({"event":"phase_end","instance":1,"net":"launch","exit":"done","result":"completed","sim_time":100}
{"event":"phase_start","instance":2,"net":"leg","depth":1,"sim_time":100}
{"event":"phase_start","instance":3,"net":"hold_depth","depth":2,"sim_time":100}
)";
    }
    if (t == 585) {
      log += R"({"event":"phase_end","instance":3,"net":"hold_depth","exit":"leak","result":"aborted","sim_time":585}
{"event":"phase_end","instance":2,"net":"leg","exit":"abort","result":"aborted","sim_time":590}
{"event":"phase_start","instance":4,"net":"emergency_surface","depth":1,"sim_time":590}
)";
    }
  }
  log += R"({"event":"phase_end","instance":4,"net":"emergency_surface","exit":"up","result":"completed","sim_time":620}
{"event":"mission_end","outcome":"aborted","exit":"closed_after_abort","reason":"a leak in the hull: the leg was abandoned","mission_sim_time":600,"sim_time":620}
)";
  return log;
}

MissionPlot survey() {
  auto r = read_text(survey_log());
  if (!r) ADD_FAILURE() << r.error().message;
  return r ? r.value() : MissionPlot{};
}

// The text of a script from the line starting with `from` to the first
// `plot` after it.
std::string section(const std::string& s, const std::string& from) {
  const auto start = s.find(from);
  if (start == std::string::npos) return {};
  const auto plot = s.find("\nplot ", start);
  return s.substr(start, plot == std::string::npos ? std::string::npos : plot - start);
}

// The last `set NAME A:B` range or `set NAME VALUE` numbers in a section.
std::vector<double> numbers_of(const std::string& s, const std::string& setting) {
  const std::regex re("\nset " + setting + R"( \[?([-0-9.e+]+)(?:[:,]([-0-9.e+]+))?)");
  std::vector<double> out;
  for (auto it = std::sregex_iterator(s.begin(), s.end(), re); it != std::sregex_iterator(); ++it) {
    out = {std::stod((*it)[1])};
    if ((*it)[2].matched) out.push_back(std::stod((*it)[2]));
  }
  return out;
}

struct Box {
  std::string text;
  bool abort = false;  // in the abort colour
  double x0, x1, y0, y1;
};

// The labels of a time panel's section as boxes in pixels, origin at the
// graph's lower left, y up; the graph is w x h pixels over the ranges
// [t0, t1] and [v0, v1] (v0 at the bottom).
std::vector<Box> label_boxes(const std::string& s, double w, double h, double t0, double t1, double v0, double v1) {
  const std::regex re(
      R"(\nset label ((?:'[^']*'(?:\."\\n"\.)?)+) at (first|graph) ([-0-9.e+]+), (first|graph) ([-0-9.e+]+)( left| right| center)?(?: offset ([-0-9.e+]+),([-0-9.e+]+))?([^\n]*))");
  std::vector<Box> out;
  for (auto it = std::sregex_iterator(s.begin(), s.end(), re); it != std::sregex_iterator(); ++it) {
    const auto& m = *it;
    std::vector<std::string> lines;
    const std::regex quoted("'([^']*)'");
    const std::string texts = m[1];
    for (auto q = std::sregex_iterator(texts.begin(), texts.end(), quoted); q != std::sregex_iterator(); ++q) {
      lines.push_back((*q)[1]);
    }
    std::size_t longest = 0;
    for (const auto& l : lines) longest = std::max(longest, l.size());
    const double x = (m[2] == "first" ? (std::stod(m[3]) - t0) / (t1 - t0) : std::stod(m[3])) * w +
                     (m[7].matched ? std::stod(m[7]) * kCharW : 0);
    const double y = (m[4] == "first" ? (std::stod(m[5]) - v0) / (v1 - v0) : std::stod(m[5])) * h +
                     (m[8].matched ? std::stod(m[8]) * kCharH : 0);
    const double width = static_cast<double>(longest) * kCharW;
    const std::string align = m[6].matched ? std::string(m[6]) : " left";
    const double left = align == " right" ? x - width : align == " center" ? x - width / 2 : x;
    // The first line is centred on y; the others go under it.
    out.push_back({fmt::format("{}", fmt::join(lines, " ")), std::string(m[9]).find("#cc0000") != std::string::npos,
                   left, left + width, y - (static_cast<double>(lines.size()) - 0.5) * kCharH, y + kCharH / 2});
  }
  return out;
}

bool overlap(const Box& a, const Box& b) { return a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1; }

std::string no_spaces(std::string s) {
  std::erase(s, ' ');
  return s;
}

TEST(TrackPlot, TrackPanelIsNotSquashed) {
  const MissionPlot p = survey();
  const std::string xy = section(gnuplot_script(p, Format::Png, "/d", "/d/plot.png"), "# The horizontal plane");
  EXPECT_NE(std::string::npos, xy.find("set size ratio -1 0.42,0.94\n")) << "one metre as long on both axes";
  const auto x = numbers_of(xy, "xrange");
  const auto y = numbers_of(xy, "yrange");
  ASSERT_EQ(2u, x.size()) << xy;
  ASSERT_EQ(2u, y.size()) << xy;
  // Everything drawn is inside, and the box is not a strip.
  for (const Point& at : p.estimated.at) {
    EXPECT_TRUE(x[0] < at.x_m && at.x_m < x[1] && y[0] < at.y_m && at.y_m < y[1]) << at.x_m << "," << at.y_m;
  }
  const double aspect = (y[1] - y[0]) / (x[1] - x[0]);
  EXPECT_GE(aspect, 0.74);
  EXPECT_LE(aspect, 1.35);

  // A leg north is widened the other way.
  std::string north;
  for (int t = 0; t <= 10; ++t) {
    north += fmt::format(R"({{"event":"telemetry","sim_time":{},"depth_m":1,"x_m":0,"y_m":{}}})"
                         "\n",
                         t, 30 * t);
  }
  auto r = read_text(north);
  ASSERT_TRUE(r) << r.error().message;
  const std::string tall = section(gnuplot_script(r.value(), Format::Png, "/d", "/d/plot.png"), "# The horizontal");
  const auto tx = numbers_of(tall, "xrange");
  const auto ty = numbers_of(tall, "yrange");
  ASSERT_EQ(2u, tx.size()) << tall;
  ASSERT_EQ(2u, ty.size()) << tall;
  EXPECT_LE((ty[1] - ty[0]) / (tx[1] - tx[0]), 1.35);
  EXPECT_LT(ty[0], 0);
  EXPECT_GT(ty[1], 300);
}

TEST(TrackPlot, TrackTickLabelsDoNotOverlap) {
  const std::string s = gnuplot_script(survey(), Format::Png, "/d", "/d/plot.png");
  const std::string xy = section(s, "# The horizontal plane");
  const auto x = numbers_of(xy, "xrange");
  const auto y = numbers_of(xy, "yrange");
  const auto xtics = numbers_of(xy, "xtics");
  const auto ytics = numbers_of(xy, "ytics");
  ASSERT_EQ(2u, x.size()) << xy;
  ASSERT_EQ(2u, y.size()) << xy;
  ASSERT_EQ(1u, ytics.size()) << "the y tick step is chosen, not left to gnuplot\n" << xy;
  ASSERT_EQ(1u, xtics.size()) << xy;
  // The box's room in the panel (0.42 x 0.94 of the picture) less the axis
  // labels and tick labels at the left and bottom and the key's three rows
  // under it, at the aspect of the ranges.
  const double room_w = 0.42 * kPictureW - 8 * kCharW;
  const double room_h = 0.94 * kPictureH - 8 * kCharH;
  const double aspect = (y[1] - y[0]) / (x[1] - x[0]);
  const double box_w = std::min(room_w, room_h / aspect);
  const double box_h = box_w * aspect;
  // Two rows of text between y tick labels; x tick labels ("-100") two
  // characters apart.
  EXPECT_GE(box_h * ytics[0] / (y[1] - y[0]), 2 * kCharH) << "y step " << ytics[0];
  EXPECT_GE(box_w * xtics[0] / (x[1] - x[0]), 6 * kCharW) << "x step " << xtics[0];
  // Enough of them to read a distance off.
  EXPECT_GE((y[1] - y[0]) / ytics[0], 2.0);
  // The time panels get gnuplot's own ticks back.
  const auto depth = s.find("# Depth");
  EXPECT_LT(s.find("set ytics autofreq"), depth);
  EXPECT_LT(s.find("set xtics autofreq"), depth);
}

TEST(TrackPlot, AbortLabelsDoNotOverlapEachOtherOrTheSeabed) {
  const MissionPlot p = survey();
  ASSERT_EQ(3u, p.aborts.size());
  const std::string s = gnuplot_script(p, Format::Png, "/d", "/d/plot.png");
  const std::string depth = section(s, "# Depth");
  const auto lmargin = numbers_of(s, "lmargin at screen");
  const auto rmargin = numbers_of(s, "rmargin at screen");
  const auto time = numbers_of(s, "xrange");  // the last: the time axis
  const auto range = numbers_of(depth, "yrange");
  const auto size = numbers_of(depth, "size");
  const auto tmargin = numbers_of(depth, "tmargin");
  ASSERT_TRUE(lmargin.size() == 1 && rmargin.size() == 1 && time.size() == 2 && range.size() == 2 && size.size() == 2 &&
              tmargin.size() == 1)
      << depth;
  const double w = (rmargin[0] - lmargin[0]) * kPictureW;
  // Under the depth graph: its (empty) tick labels.
  const double h = size[1] * kPictureH - (tmargin[0] + 2) * kCharH;
  const auto boxes = label_boxes(depth, w, h, time[0], time[1], range[0], range[1]);

  // Every abort's text is written.
  std::string written;
  for (const Box& b : boxes) {
    if (b.abort) written += b.text;
  }
  for (const AbortMark& m : p.aborts)
    EXPECT_NE(std::string::npos, no_spaces(written).find(no_spaces(m.label))) << m.label;

  // No two labels (the aborts' and the phases') cover each other.
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    for (std::size_t j = i + 1; j < boxes.size(); ++j) {
      EXPECT_FALSE(overlap(boxes[i], boxes[j])) << "'" << boxes[i].text << "' and '" << boxes[j].text << "'";
    }
  }
  // No abort label covers the seabed, nor the depth line, nor the key's
  // rows (depth, setpoint, seabed) at the top of the right margin.
  auto y_of = [&](double v) { return (v - range[0]) / (range[1] - range[0]) * h; };
  for (const Box& b : boxes) {
    if (!b.abort) continue;
    for (const Series* series : {&p.seabed_m, &p.depth_m}) {
      for (std::size_t k = 0; k < series->size(); ++k) {
        const double x = (series->time_s[k] - time[0]) / (time[1] - time[0]) * w;
        const double y = y_of(series->value[k]);
        if (b.x0 <= x && x <= b.x1 && b.y0 <= y && y <= b.y1) {
          ADD_FAILURE() << "'" << b.text << "' covers " << (series == &p.seabed_m ? "the seabed" : "the depth")
                        << " at t " << series->time_s[k];
          break;
        }
      }
    }
    if (b.x1 > w) {
      EXPECT_LE(b.y1, h - 3 * kCharH) << "'" << b.text << "' is in the key";
    }
  }
}

TEST(TrackLayout, TickStepIsOneTwoOrFiveTimesAPowerOfTen) {
  EXPECT_DOUBLE_EQ(50.0, layout::tick_step(275, 8));
  EXPECT_DOUBLE_EQ(50.0, layout::tick_step(250, 5));
  EXPECT_DOUBLE_EQ(0.2, layout::tick_step(1.5, 8));
  EXPECT_DOUBLE_EQ(1.0, layout::tick_step(8, 8));
  EXPECT_DOUBLE_EQ(2000.0, layout::tick_step(12000, 8));
  EXPECT_DOUBLE_EQ(1.0, layout::tick_step(0, 8));
  EXPECT_DOUBLE_EQ(1.0, layout::tick_step(INFINITY, 8));
}

TEST(TrackLayout, SpreadKeepsOrderAndDistance) {
  using V = std::vector<double>;
  EXPECT_EQ((V{50, 200}), layout::spread({50, 200}, 20, 400));
  // Close at the end: pushed apart and back inside.
  EXPECT_EQ((V{350, 370, 390}), layout::spread({388, 395, 399}, 20, 400));
  // At the start too.
  EXPECT_EQ((V{10, 30}), layout::spread({0, 1}, 20, 400));
  // Too many for the axis: evenly spread.
  EXPECT_EQ((V{50, 150, 250, 350}), layout::spread({1, 2, 3, 4}, 150, 400));
  EXPECT_TRUE(layout::spread({}, 20, 400).empty());
}

}  // namespace
}  // namespace strata::plot
