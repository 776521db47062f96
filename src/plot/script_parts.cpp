#include "plot/script_parts.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include <fmt/format.h>

#include "core/file.h"

namespace strata::plot::script {

namespace fs = std::filesystem;

// A gnuplot single-quoted string: nothing is special inside but the quote,
// written twice, and the end of the line: gnuplot ends a command at a
// newline whatever quote is open, so a net name in a log with
// "\nprint system('...')" in it ran that command when the log was plotted.
// Control characters (newlines, carriage returns, NUL) become spaces.
std::string gp_string(std::string_view text) {
  std::string out = "'";
  for (char c : text) {
    const auto u = static_cast<unsigned char>(c);
    out += u < 0x20 || u == 0x7f ? ' ' : c;
    if (c == '\'') out += '\'';
  }
  return out + "'";
}

// Numbers in the script: enough digits for a microsecond in a day.
std::string num(double v) { return fmt::format("{:.12g}", v); }

core::Result<void> write_series(const fs::path& file, const Series& s, bool break_at_wrap) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    // A blank line lifts the pen: a heading crossing north is no sweep
    // across the whole panel.
    if (break_at_wrap && i > 0 && std::abs(s.value[i] - s.value[i - 1]) > 180.0) out += "\n";
    out += fmt::format("{} {}\n", s.time_s[i], s.value[i]);
  }
  return write_scratch(file, out);
}

core::Result<void> write_scratch(const fs::path& file, const std::string& text) {
  return core::write_file_atomically(file, text, {.durable = false});
}

namespace {
bool completed(const PhaseBand& b) { return b.ended && b.result == "completed"; }
}  // namespace

// The rectangles of the depth-1 bands (every panel), and with `nested` the
// strips of deeper phases (the depth panel only).
void bands(std::string& s, const MissionPlot& plot, bool nested) {
  std::size_t shade = 0;
  for (const PhaseBand& b : plot.phases) {
    if (b.depth == 1) {
      const char* colour = completed(b) ? kBandColours[shade++ % 2] : kFailedBandColour;
      s += fmt::format(
          "set object rect from first {}, graph 0 to first {}, graph 1 fc rgb '{}' "
          "fs solid 0.15 noborder behind\n",
          num(b.start_s), num(b.end_s), colour);
    } else if (nested) {
      const double top = 1.0 - kNestedStrip * (b.depth - 2);
      s += fmt::format(
          "set object rect from first {}, graph {} to first {}, graph {} fc rgb '{}' "
          "fs solid 0.45 noborder behind\n",
          num(b.start_s), num(top - kNestedStrip * 0.8), num(b.end_s), num(top), kNestedBandColour);
    }
  }
}

std::vector<std::string> wrapped(const std::string& text, std::size_t width) {
  std::vector<std::string> lines;
  std::istringstream words(text);
  std::string word;
  while (words >> word) {
    if (!lines.empty() && (width == 0 || lines.back().size() + 1 + word.size() <= width)) {
      lines.back() += " " + word;
    } else {
      lines.push_back(word);
    }
  }
  if (lines.empty()) lines.emplace_back();
  return lines;
}

// Abort lines (every panel) and, with `labels`, their text in rows from the
// bottom, on the side of the line nearer the middle of the run.
void aborts(std::string& s, const MissionPlot& plot, bool labels) {
  const double middle = (plot.first_s + plot.last_s) / 2;
  std::size_t row = 0;
  for (const AbortMark& m : plot.aborts) {
    s += fmt::format("set arrow from first {0}, graph 0 to first {0}, graph 1 nohead lc rgb '{1}' {2} front\n",
                     num(m.time_s), kAbortColour, m.mission ? "dt 1 lw 2.5" : "dt 2 lw 1.5");
    if (!labels) continue;
    const bool right_half = m.time_s > middle;
    s += fmt::format("set label {} at first {}, graph {} {} offset {},0 tc rgb '{}' front\n", gp_string(m.label),
                     num(m.time_s), num(0.04 + 0.06 * static_cast<double>(row++)), right_half ? "right" : "left",
                     right_half ? "-0.6" : "0.6", kAbortColour);
  }
}

// The names of the depth-1 phases above the depth panel, where they hide no
// data, in two rows taken in turn so that a short phase's name does not run
// into the next one's.
void phase_labels(std::string& s, const MissionPlot& plot) {
  std::size_t row = 0;
  for (const PhaseBand& b : plot.phases) {
    if (b.depth != 1) continue;
    s += fmt::format("set label {} at first {}, graph 1 left offset 0.4,{} front\n", gp_string(b.net), num(b.start_s),
                     row++ % 2 == 0 ? "0.6" : "1.7");
  }
}

std::pair<double, double> depth_range(const MissionPlot& plot, const Series* extra) {
  double lo = 0.0;  // the surface is always shown
  double hi = 0.0;
  for (const Series* s : {&plot.depth_m, &plot.filtered_depth_m, &plot.setpoint_m, extra}) {
    if (!s) continue;
    for (double v : s->value) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  const double pad = std::max(0.05 * (hi - lo), 0.05);
  return {lo - pad, hi + pad};
}

}  // namespace strata::plot::script
