#include "plot/track_script.h"

#include <algorithm>

#include <fmt/format.h>

#include "plot/script_parts.h"
#include "plot/track_layout.h"

namespace strata::plot {
namespace {

namespace fs = std::filesystem;
using namespace script;

constexpr const char* kTrueColour = "#777777";
constexpr const char* kPlanColour = "#ee7733";
constexpr const char* kFixColour = "#cc3311";
constexpr const char* kSeabedColour = "#8c510a";
constexpr const char* kAltitudeColour = "#aa3377";
constexpr std::size_t kLegendWrap = 26;  // characters: an abort's text fits the right margin

// The picture's size, and where the time panels' graphs sit across it.
constexpr int kWidthPx = 1400;
constexpr int kHeightPx = 800;
constexpr double kTimeLeft = 0.50;
constexpr double kTimeRight = 0.80;
constexpr double kDepthTopChars = 3.5;  // the depth panel's top margin: the phase names

std::string xy(const Point& p) { return fmt::format("{} {}\n", p.x_m, p.y_m); }

// The planned lines of one kind, a blank line after each so that gnuplot
// lifts the pen between them.
std::string lines(const MissionPlot& plot, bool track) {
  std::string out;
  for (const PlannedLeg& leg : plot.plan) {
    if (leg.track == track && leg.from_known) out += xy(leg.from) + xy(leg.to) + "\n";
  }
  return out;
}

std::string file(const fs::path& folder, const char* name) { return gp_string((folder / name).string()); }

// One time panel's settings: where it sits, what its y axis is, whether the
// time axis is labelled under it.
void time_panel(std::string& s, double origin, double size, bool bottom) {
  s += "unset object\nunset label\nunset arrow\n";
  s += fmt::format("set origin 0.42,{}\nset size 0.58,{}\n", num(origin), num(size));
  s += bottom ? "set xlabel 'simulated time (s)'\nset format x\n" : "set xlabel\nset format x ''\n";
}

}  // namespace

core::Result<void> write_track_data(const MissionPlot& plot, const fs::path& folder) {
  for (const auto& [name, path] : {std::pair{"track.dat", &plot.estimated}, std::pair{"true_track.dat", &plot.truth}}) {
    if (path->empty()) continue;
    std::string text;
    for (const Point& p : path->at) text += xy(p);
    auto written = write_scratch(folder / name, text);
    if (!written) return written;
  }
  std::string waypoints;
  for (const PlannedLeg& leg : plot.plan) waypoints += xy(leg.to);
  std::string fixes;
  for (const Fix& f : plot.fixes) fixes += xy(f.at);
  for (const auto& [name, text] :
       {std::pair{"track_lines.dat", lines(plot, true)}, std::pair{"goto_lines.dat", lines(plot, false)},
        std::pair{"waypoints.dat", waypoints}, std::pair{"fixes.dat", fixes}}) {
    if (text.empty()) continue;
    auto written = write_scratch(folder / name, text);
    if (!written) return written;
  }
  for (const auto& [name, series] :
       {std::pair{"altitude.dat", &plot.altitude_m}, std::pair{"seabed.dat", &plot.seabed_m}}) {
    if (series->empty()) continue;
    auto written = write_series(folder / name, *series, false);
    if (!written) return written;
  }
  return {};
}

std::string open_water_script(const MissionPlot& plot, Format format, const fs::path& data_folder,
                              const fs::path& output) {
  const bool heading = !plot.heading_deg.empty();
  const bool altitude = !plot.altitude_m.empty();
  std::string s = "# Written by `strata plot`; run it again with `gnuplot plot.gp`.\n";
  s += "set encoding utf8\n";
  if (format == Format::Svg) {
    s += fmt::format("set terminal svg size {},{} noenhanced font 'sans,11' background rgb 'white'\n", kWidthPx,
                     kHeightPx);
  } else {
    s += fmt::format("set terminal png size {},{} noenhanced background rgb 'white'\n", kWidthPx, kHeightPx);
  }
  s += fmt::format("set output {}\n", gp_string(output.string()));
  s += fmt::format("set multiplot title {}\n", gp_string(plot.title()));
  s += "set grid back lc rgb '#dddddd'\n";

  s += "\n# The horizontal plane: x east, y north, one metre as long on both axes.\n";
  s += "set origin 0,0\nset size ratio -1 0.42,0.94\n";
  s += "set key below\n";
  s += "set xlabel 'x east (m)'\nset ylabel 'y north (m)'\n";
  // Ranges and ticks from the data (track_layout.h): autoscaled, a straight
  // leg made the box a strip and crowded its y tick labels.
  const layout::XyFrame frame = layout::xy_frame(plot);
  s += fmt::format("set xrange [{}:{}]\nset yrange [{}:{}]\n", num(frame.x0), num(frame.x1), num(frame.y0),
                   num(frame.y1));
  s += fmt::format("set xtics {0}\nset ytics {0}\n", num(frame.step));
  std::string curves;
  auto add = [&](const std::string& curve) { curves += (curves.empty() ? "plot " : ", \\\n     ") + curve; };
  if (!lines(plot, true).empty()) {
    add(fmt::format("{} using 1:2 with lines lw 1.5 lc rgb '{}' title 'planned track'",
                    file(data_folder, "track_lines.dat"), kPlanColour));
  }
  if (!lines(plot, false).empty()) {
    add(fmt::format("{} using 1:2 with lines lw 1.5 dt 2 lc rgb '{}' title 'planned goto_xy'",
                    file(data_folder, "goto_lines.dat"), kPlanColour));
  }
  if (!plot.plan.empty()) {
    add(fmt::format("{} using 1:2 with points pt 6 ps 1.6 lw 1.5 lc rgb '{}' title 'waypoint'",
                    file(data_folder, "waypoints.dat"), kPlanColour));
  }
  if (!plot.truth.empty()) {
    add(fmt::format("{} using 1:2 with lines lw 1 dt 3 lc rgb '{}' title 'true track'",
                    file(data_folder, "true_track.dat"), kTrueColour));
  }
  add(fmt::format("{} using 1:2 with lines lw 2 lc rgb '{}' title 'estimated track'", file(data_folder, "track.dat"),
                  kDepthColour));
  add(fmt::format("{} every ::0::0 using 1:2 with points pt 5 ps 1.2 lc rgb '{}' title 'start'",
                  file(data_folder, "track.dat"), kDepthColour));
  if (!plot.fixes.empty()) {
    add(fmt::format("{} using 1:2 with points pt 9 ps 1.6 lc rgb '{}' title 'GPS fix'", file(data_folder, "fixes.dat"),
                    kFixColour));
  }
  s += curves + "\n";
  s += "set size noratio\nset xtics autofreq\nset ytics autofreq\n";

  // The time panels share their left and right edges, so their axes line up.
  s += "\n# Against time.\n";
  s += fmt::format("set lmargin at screen {}\nset rmargin at screen {}\n", num(kTimeLeft), num(kTimeRight));
  // A short sample: at the usual length the seabed's title ran into the graph.
  s += "set key default\nset key outside right top samplen 2\n";
  const double span = plot.last_s > plot.first_s ? plot.last_s - plot.first_s : 1.0;
  s += fmt::format("set xrange [{}:{}]\n", num(plot.first_s), num(plot.first_s + span * 1.02));
  const double lower = heading ? 0.26 : 0.0;  // the heading panel's share
  const double depth_origin = altitude ? lower + (0.94 - lower) * 0.42 : lower;

  const bool depth_at_bottom = !altitude && !heading;
  const double depth_size = 0.94 - depth_origin;
  const layout::DepthPanel panel{
      .first_s = plot.first_s,
      .last_s = plot.first_s + span * 1.02,
      .width_px = (kTimeRight - kTimeLeft) * kWidthPx,
      // The bottom margin is a row of (empty) tick labels, or those and
      // the time axis's name.
      .height_px = depth_size * kHeightPx - (kDepthTopChars + (depth_at_bottom ? 3.5 : 2.0)) * layout::kCharHeightPx,
      .key_rows = 1 + (plot.setpoint_m.empty() ? 0u : 1u) + (plot.seabed_m.empty() ? 0u : 1u),
      .wrap = kLegendWrap,
  };
  // The abort numbers get a strip of their own under the deepest data (the
  // seabed): the range is stretched down by that part of the panel.
  auto [shallow, deep] = depth_range(plot, &plot.seabed_m);
  const double strip = layout::abort_strip(plot, panel);
  deep += (deep - shallow) * strip / (1 - strip);
  s += "\n# Depth, positive down, with the seabed under it.\n";
  time_panel(s, depth_origin, depth_size, depth_at_bottom);
  s += fmt::format("set yrange [{}:{}]\n", num(deep), num(shallow));
  s += fmt::format("set tmargin {}\nset ylabel 'depth (m)'\n", num(kDepthTopChars));
  bands(s, plot, true);
  phase_labels(s, plot);
  // Numbered, with their texts beside the key: the texts are long, and a
  // phase's abort and the mission's end come seconds apart, so beside their
  // lines they covered each other and the data.
  s += layout::numbered_aborts(plot, panel);
  s += fmt::format("plot {} using 1:2 with lines lw 2 lc rgb '{}' title 'depth'", file(data_folder, "depth.dat"),
                   kDepthColour);
  if (!plot.setpoint_m.empty()) {
    s += fmt::format(", \\\n     {} using 1:2 with steps lw 1.5 dt 2 lc rgb '{}' title 'setpoint'",
                     file(data_folder, "setpoint.dat"), kSetpointColour);
  }
  if (!plot.seabed_m.empty()) {
    s += fmt::format(", \\\n     {} using 1:2 with lines lw 2 lc rgb '{}' title 'seabed (depth + altitude)'",
                     file(data_folder, "seabed.dat"), kSeabedColour);
  }
  s += "\n";

  if (altitude) {
    s += "\n# Altitude above the seabed, from the sonar altimeter.\n";
    time_panel(s, lower, depth_origin - lower + 0.02, !heading);
    s += "set autoscale y\nset yrange [0:*]\nset ytics autofreq\nset tmargin 1\nset ylabel 'altitude (m)'\n";
    bands(s, plot, false);
    aborts(s, plot, false);
    s += fmt::format("plot {} using 1:2 with lines lw 1.5 lc rgb '{}' title 'altitude'\n",
                     file(data_folder, "altitude.dat"), kAltitudeColour);
  }
  if (heading) {
    const bool signed_heading = *std::min_element(plot.heading_deg.value.begin(), plot.heading_deg.value.end()) < 0;
    s += "\n# Heading.\n";
    time_panel(s, 0, lower + 0.02, true);
    s += signed_heading ? "set yrange [-180:180]\nset ytics -180,90,180\n" : "set yrange [0:360]\nset ytics 0,90,360\n";
    s += "set tmargin 1\nset ylabel 'heading (deg)'\n";
    bands(s, plot, false);
    aborts(s, plot, false);
    s += fmt::format("plot {} using 1:2 with lines lw 1.5 lc rgb '{}' title 'heading'\n",
                     file(data_folder, "heading.dat"), kHeadingColour);
  }
  s += "unset multiplot\n";
  return s;
}

}  // namespace strata::plot
