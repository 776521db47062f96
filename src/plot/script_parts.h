#pragma once
// The pieces of a gnuplot script that the tank plot (gnuplot.cpp) and the
// open-water plot (track_script.cpp) share: quoting, numbers, the phase bands
// and abort marks on a time axis, and the data files.
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/result.h"
#include "plot/plot_log.h"

namespace strata::plot::script {

inline constexpr const char* kDepthColour = "#0044aa";
inline constexpr const char* kFilteredColour = "#33bbee";
inline constexpr const char* kSetpointColour = "#ee7733";
inline constexpr const char* kHeadingColour = "#009988";
inline constexpr const char* kAbortColour = "#cc0000";
inline constexpr const char* kBandColours[] = {"#4477aa", "#228833"};
inline constexpr const char* kFailedBandColour = "#ee6677";
inline constexpr const char* kNestedBandColour = "#555555";
inline constexpr double kNestedStrip = 0.03;  // graph height of one nesting level's strip

// A gnuplot single-quoted string: nothing is special inside but the quote,
// written twice.
std::string gp_string(std::string_view text);

// Numbers in the script: enough digits for a microsecond in a day.
std::string num(double v);

// "TIME VALUE" lines; with break_at_wrap a blank line where the value jumps
// by more than 180 (a heading crossing north). Io on failure.
core::Result<void> write_series(const std::filesystem::path& file, const Series& s, bool break_at_wrap);

// A file of the plot's temporary folder (data, the script), written whole
// and not synced: gnuplot reads it at once and the folder goes after.
// "cannot write 'FILE': reason" on failure.
core::Result<void> write_scratch(const std::filesystem::path& file, const std::string& text);

// The rectangles of the depth-1 bands (every time panel), and with `nested`
// the strips of deeper phases (the depth panel only).
void bands(std::string& s, const MissionPlot& plot, bool nested);

// Abort lines (every time panel) and, with `labels`, their text beside them
// (the tank plot; the open-water plot numbers them: track_layout.h).
void aborts(std::string& s, const MissionPlot& plot, bool labels);

// `text` in lines of at most `width` characters, broken at spaces (a word
// longer stays whole); one line with width 0.
std::vector<std::string> wrapped(const std::string& text, std::size_t width);

// The names of the depth-1 phases above the depth panel.
void phase_labels(std::string& s, const MissionPlot& plot);

// The depth axis's range, shallow end first, the surface always in it;
// `extra` (the seabed) widens it.
std::pair<double, double> depth_range(const MissionPlot& plot, const Series* extra = nullptr);

}  // namespace strata::plot::script
