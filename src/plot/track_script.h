#pragma once
// The open-water plot: a MissionPlot whose telemetry has x_m and y_m
// (MissionPlot::has_track). One picture, two columns:
//
// - left, the horizontal plane with equal scales on both axes: the estimated
//   track (thick), the true track (thin, dashed), the planned lines (`track`
//   solid, `goto_xy` dashed from where the estimate stood) and their
//   waypoints, the accepted GPS fixes, and the start;
// - right, on one time axis with the phase bands and abort marks: depth with
//   its setpoint and the seabed (depth + altitude, from the altimeter), then
//   the altitude, then the heading when the log has it.
#include <filesystem>
#include <string>

#include "core/result.h"
#include "plot/gnuplot.h"
#include "plot/plot_log.h"

namespace strata::plot {

// track.dat, true_track.dat, track_lines.dat, goto_lines.dat (segments
// separated by blank lines), waypoints.dat, fixes.dat ("X Y" lines),
// altitude.dat and seabed.dat ("TIME VALUE"): the non-empty ones, into
// `folder`. Io on failure. write_data calls it for a log with a track.
core::Result<void> write_track_data(const MissionPlot& plot, const std::filesystem::path& folder);

// The script for a log with a track; gnuplot_script calls it.
std::string open_water_script(const MissionPlot& plot, Format format, const std::filesystem::path& data_folder,
                              const std::filesystem::path& output);

}  // namespace strata::plot
