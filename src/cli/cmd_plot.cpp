// `strata plot LOG [-o FILE.svg|FILE.png]`: a mission log drawn by gnuplot
// (plot/gnuplot.h): depth and setpoint against time with the phases as
// bands and the aborts marked, and the heading when the log has it.
#include <filesystem>
#include <iostream>
#include <memory>

#include <fmt/format.h>

#include "core/mission_language.h"
#include "cli/commands.h"
#include "cli/exit_codes.h"
#include "cli/verbosity.h"
#include "plot/gnuplot.h"
#include "plot/plot_log.h"

namespace strata::cli {
namespace {

namespace fs = std::filesystem;

// sysexits' EX_UNAVAILABLE: a program strata needs is not installed. Only
// `strata plot` needs another program, so it is not among the common codes.

struct PlotOptions {
  std::string log;
  std::string output;
  bool keep_script = false;
  VerbosityFlags verbosity;
};

int run_plot(const PlotOptions& o) {
  fs::path output = o.output;
  if (output.empty()) output = fs::path(o.log).replace_extension(".svg");
  const auto format = plot::format_for(output);
  if (!format) {
    std::cerr << fmt::format("strata plot: '{}': the output is a .svg or a .png file\n", output.string());
    return kExitUsage;
  }
  if (core::mission_language(o.log) != core::MissionLanguage::None) {
    std::cerr << fmt::format(
        "strata plot: '{}' is a mission, not a run's log; `strata run {} --log run.jsonl` "
        "writes one to plot\n",
        o.log, o.log);
    return kExitUsage;
  }
  auto log = plot::read_log_file(o.log);
  if (!log) {
    std::cerr << "strata plot: " << log.error().message << "\n";
    return exit_code_for_input(log.error());
  }
  for (const std::string& note : log.value().notes) std::cerr << "strata plot: " << note << "\n";
  if (log.value().skipped_notes > 0) {
    std::cerr << fmt::format("strata plot: and {} more lines skipped in part\n", log.value().skipped_notes);
  }
  plot::RenderOptions options;
  options.format = *format;
  options.output = output;
  options.keep_folder = o.keep_script;
  const plot::Rendered r = plot::render(log.value(), options);
  if (!r.kept_folder.empty()) {
    std::cerr << fmt::format("kept the gnuplot script and data in {}\n", r.kept_folder.string());
  }
  if (!r.warnings.empty()) std::cerr << "gnuplot: " << r.warnings << "\n";
  switch (r.status) {
    case plot::RenderStatus::Ok:
      if (o.verbosity.level() != Verbosity::Quiet) std::cerr << fmt::format("wrote {}\n", output.string());
      return kExitOk;
    case plot::RenderStatus::GnuplotMissing: std::cerr << "strata plot: " << r.message << "\n"; return kExitUnavailable;
    case plot::RenderStatus::GnuplotFailed: std::cerr << "strata plot: " << r.message << "\n"; return kExitInternal;
    case plot::RenderStatus::Io: std::cerr << "strata plot: " << r.message << "\n"; return kExitIo;
  }
  return kExitInternal;
}

}  // namespace

Runner add_plot_command(CLI::App& app) {
  auto o = std::make_shared<PlotOptions>();
  auto* cmd = app.add_subcommand(
      "plot",
      "Draw a mission log with gnuplot: depth and setpoint against time, the phases as bands, the aborts marked, "
      "and the heading when the log has it");
  cmd->add_option("log", o->log, "A mission log (JSON Lines, from `strata run --log FILE`)")->required();
  cmd->add_option("-o,--output", o->output,
                  "The picture: FILE.svg or FILE.png (default: LOG with .svg for its extension)");
  cmd->add_flag("--keep-script", o->keep_script,
                "Keep the temporary folder with the gnuplot script (plot.gp), its data and gnuplot's stderr");
  cmd->footer(
      "Example:\n"
      "  strata run missions/tank/tank.coral --scenario leak_phase2 --log run.jsonl\n"
      "  strata plot run.jsonl                # writes run.svg\n"
      "  strata plot run.jsonl -o run.png\n"
      "Needs gnuplot (Debian: gnuplot-nox). docs/plot.md says what is drawn.\n"
      "Exit 0 when written; 65 for a log without telemetry or with a malformed line (named by its number);\n"
      "69 when gnuplot is not installed; 70 when gnuplot fails (its messages are shown); 74 when a file\n"
      "cannot be read or written.");
  add_verbosity_flags(cmd, o->verbosity, "");
  return [o] { return run_plot(*o); };
}

}  // namespace strata::cli
