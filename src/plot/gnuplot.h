#pragma once
// A MissionPlot drawn by gnuplot: the data files and the script written to a
// temporary folder, gnuplot run on them as a child process (no shell), the
// picture copied to where it was asked for.
//
// The picture: depth (measured, filtered) and setpoint against simulated
// time, depth positive down; the phases of the global net as shaded bands
// labelled with their net's name (red when they did not complete); phases
// started by phases as thin grey strips along the top of the depth panel;
// aborts as red dashed lines with their label; and, when the telemetry has
// heading_deg, a second panel with the heading on the same time axis.
#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "core/result.h"
#include "plot/plot_log.h"

namespace strata::plot {

enum class Format { Svg, Png };

// The format a file name asks for (.svg, .png, any case); nullopt for others.
std::optional<Format> format_for(const std::filesystem::path& file);

// Writes depth.dat, filtered_depth.dat, setpoint.dat and heading.dat (the
// non-empty series: "TIME VALUE" lines) into `folder`. Io on failure.
core::Result<void> write_data(const MissionPlot& plot, const std::filesystem::path& folder);

// The gnuplot script drawing `plot` into `output`, reading the files
// write_data put in `data_folder`. Deterministic: the same plot gives the
// same text.
std::string gnuplot_script(const MissionPlot& plot, Format format, const std::filesystem::path& data_folder,
                           const std::filesystem::path& output);

// The first executable `name` in the folders of PATH.
std::optional<std::filesystem::path> find_on_path(std::string_view name);

enum class RenderStatus {
  Ok,
  GnuplotMissing,  // no gnuplot on PATH
  GnuplotFailed,   // it exited non-zero, died, made no picture, or ran past the bound
  Io,              // the temporary folder or the output could not be written
};

struct [[nodiscard]] Rendered {
  RenderStatus status = RenderStatus::Ok;
  std::string message;                // what went wrong (gnuplot's stderr when it failed)
  std::string warnings;               // gnuplot's stderr when it succeeded anyway
  std::filesystem::path kept_folder;  // with keep_folder: where the script and data are
  bool ok() const { return status == RenderStatus::Ok; }
};

struct RenderOptions {
  Format format = Format::Svg;
  std::filesystem::path output;
  bool keep_folder = false;                 // leave the temporary folder (script, data, stderr) behind
  std::chrono::milliseconds bound{60'000};  // wall time gnuplot may take; killed after
};

// Draws `plot` into options.output. Blocks until gnuplot ends or the bound
// passes. The temporary folder is under std::filesystem::temp_directory_path()
// and is removed unless options.keep_folder.
Rendered render(const MissionPlot& plot, const RenderOptions& options);

}  // namespace strata::plot
