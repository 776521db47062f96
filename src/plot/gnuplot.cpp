#include "plot/gnuplot.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "core/file.h"
#include "plot/script_parts.h"
#include "plot/track_script.h"

extern char** environ;

namespace strata::plot {

namespace fs = std::filesystem;
using namespace script;  // the pieces shared with track_script.cpp

std::optional<Format> format_for(const fs::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".svg") return Format::Svg;
  if (ext == ".png") return Format::Png;
  return std::nullopt;
}

core::Result<void> write_data(const MissionPlot& plot, const fs::path& folder) {
  const std::pair<const char*, const Series*> files[] = {{"depth.dat", &plot.depth_m},
                                                         {"filtered_depth.dat", &plot.filtered_depth_m},
                                                         {"setpoint.dat", &plot.setpoint_m},
                                                         {"heading.dat", &plot.heading_deg}};
  for (const auto& [name, series] : files) {
    if (series->empty()) continue;
    auto written = write_series(folder / name, *series, series == &plot.heading_deg);
    if (!written) return written;
  }
  if (plot.has_track()) return write_track_data(plot, folder);
  return {};
}

std::string gnuplot_script(const MissionPlot& plot, Format format, const fs::path& data_folder,
                           const fs::path& output) {
  if (plot.has_track()) return open_water_script(plot, format, data_folder, output);
  const bool heading = !plot.heading_deg.empty();
  const int height = heading ? 800 : 600;
  std::string s = "# Written by `strata plot`; run it again with `gnuplot plot.gp`.\n";
  s += "set encoding utf8\n";
  if (format == Format::Svg) {
    s += fmt::format("set terminal svg size 1100,{} noenhanced font 'sans,11' background rgb 'white'\n", height);
  } else {
    s += fmt::format("set terminal png size 1100,{} noenhanced background rgb 'white'\n", height);
  }
  s += fmt::format("set output {}\n", gp_string(output.string()));
  s += fmt::format("set multiplot title {}\n", gp_string(plot.title()));
  // Both panels share their left and right edges, so their time axes line up.
  s += "set lmargin at screen 0.08\nset rmargin at screen 0.80\n";
  s += "set key outside right top\nset grid back lc rgb '#dddddd'\n";
  // A little room after the end, so that a mark there is not the border.
  const double span = plot.last_s > plot.first_s ? plot.last_s - plot.first_s : 1.0;
  s += fmt::format("set xrange [{}:{}]\n", num(plot.first_s), num(plot.first_s + span * 1.02));

  const auto [shallow, deep] = depth_range(plot);
  s += "\n# Depth, positive down.\n";
  s += heading ? "set origin 0,0.36\nset size 1,0.60\n" : "set origin 0,0\nset size 1,0.94\n";
  s += fmt::format("set yrange [{}:{}]\n", num(deep), num(shallow));
  s += "set tmargin 3.5\n";  // room for the phase names
  s += "set ylabel 'depth (m)'\n";
  s += heading ? "set xlabel\nset format x ''\n" : "set xlabel 'simulated time (s)'\n";
  bands(s, plot, true);
  phase_labels(s, plot);
  aborts(s, plot, true);
  const fs::path depth = data_folder / "depth.dat";
  s += fmt::format("plot {} using 1:2 with lines lw 2 lc rgb '{}' title 'depth'", gp_string(depth.string()),
                   kDepthColour);
  if (!plot.filtered_depth_m.empty()) {
    s += fmt::format(", \\\n     {} using 1:2 with lines lw 1 lc rgb '{}' title 'filtered depth'",
                     gp_string((data_folder / "filtered_depth.dat").string()), kFilteredColour);
  }
  if (!plot.setpoint_m.empty()) {
    s += fmt::format(", \\\n     {} using 1:2 with steps lw 1.5 dt 2 lc rgb '{}' title 'setpoint'",
                     gp_string((data_folder / "setpoint.dat").string()), kSetpointColour);
  }
  s += "\n";

  if (heading) {
    const bool signed_heading = *std::min_element(plot.heading_deg.value.begin(), plot.heading_deg.value.end()) < 0;
    s += "\n# Heading, on the same time axis.\n";
    s += "unset object\nunset label\nunset arrow\n";
    s += "set origin 0,0\nset size 1,0.38\nset tmargin 1\n";
    s += signed_heading ? "set yrange [-180:180]\n" : "set yrange [0:360]\n";
    s += signed_heading ? "set ytics -180,90,180\n" : "set ytics 0,90,360\n";
    s += "set ylabel 'heading (deg)'\nset xlabel 'simulated time (s)'\nset format x\n";
    bands(s, plot, false);
    aborts(s, plot, false);
    s += fmt::format("plot {} using 1:2 with lines lw 1.5 lc rgb '{}' title 'heading'\n",
                     gp_string((data_folder / "heading.dat").string()), kHeadingColour);
  }
  s += "unset multiplot\n";
  return s;
}

std::optional<fs::path> find_on_path(std::string_view name) {
  const char* path = std::getenv("PATH");
  if (!path) return std::nullopt;
  std::istringstream folders(path);
  std::string folder;
  while (std::getline(folders, folder, ':')) {
    if (folder.empty()) folder = ".";
    fs::path candidate = fs::path(folder) / name;
    std::error_code ec;
    if (fs::is_regular_file(candidate, ec) && access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return std::nullopt;
}

namespace {

// The largest picture put in place: far beyond any plot gnuplot draws here.
constexpr std::size_t kMaxPictureBytes = std::size_t{256} << 20;

// What gnuplot wrote to its stderr file ("" if it cannot be read; a
// gnuplot that writes more than a few megabytes of messages is not heard).
std::string read_text(const fs::path& file) {
  auto text = core::read_regular_file(file.string(), std::size_t{4} << 20);
  if (!text) return {};
  std::string s = std::move(text).value();
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) s.pop_back();
  return s;
}

// Runs `gnuplot script` with stdin and stdout on /dev/null and stderr into
// `stderr_file`; waits at most `bound`, then kills it by its pid.
Rendered run_gnuplot(const fs::path& gnuplot, const fs::path& script, const fs::path& stderr_file,
                     std::chrono::milliseconds bound) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, stderr_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::string program = gnuplot.string();
  std::string script_path = script.string();
  char* argv[] = {program.data(), script_path.data(), nullptr};
  pid_t pid = -1;
  const int spawned = posix_spawn(&pid, program.c_str(), &actions, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) {
    return {RenderStatus::GnuplotFailed, fmt::format("cannot start {}: {}", program, std::strerror(spawned)), {}, {}};
  }
  const auto deadline = std::chrono::steady_clock::now() + bound;
  int status = 0;
  for (;;) {
    const pid_t done = waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (done < 0 && errno != EINTR) {
      return {RenderStatus::GnuplotFailed, fmt::format("waiting for gnuplot: {}", std::strerror(errno)), {}, {}};
    }
    if (std::chrono::steady_clock::now() >= deadline) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      return {RenderStatus::GnuplotFailed,
              fmt::format("gnuplot was still running after {} ms and was stopped", bound.count()),
              {},
              {}};
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  std::string err = read_text(stderr_file);
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return {RenderStatus::Ok, {}, std::move(err), {}};
  std::string why = WIFEXITED(status) ? fmt::format("gnuplot exited with status {}", WEXITSTATUS(status))
                                      : fmt::format("gnuplot was killed by signal {}", WTERMSIG(status));
  return {RenderStatus::GnuplotFailed, err.empty() ? why : fmt::format("{}:\n{}", why, err), {}, {}};
}

Rendered render_in(const MissionPlot& plot, const RenderOptions& o, const fs::path& folder) {
  auto written = write_data(plot, folder);
  if (!written) return {RenderStatus::Io, written.error().message, {}, {}};
  const fs::path picture = folder / (o.format == Format::Svg ? "plot.svg" : "plot.png");
  const fs::path script = folder / "plot.gp";
  if (auto w = write_scratch(script, gnuplot_script(plot, o.format, folder, picture)); !w) {
    return {RenderStatus::Io, w.error().message, {}, {}};
  }
  auto gnuplot = find_on_path("gnuplot");
  if (!gnuplot) return {RenderStatus::GnuplotMissing, "gnuplot not found: install gnuplot-nox", {}, {}};
  Rendered r = run_gnuplot(*gnuplot, script, folder / "gnuplot.stderr", o.bound);
  if (!r.ok()) return r;
  std::error_code ec;
  if (fs::file_size(picture, ec) == 0 || ec) {
    return {RenderStatus::GnuplotFailed, fmt::format("gnuplot exited without drawing {}", picture.string()), {}, {}};
  }
  // gnuplot draws inside the folder, and the picture is then put in place
  // whole: a failed run never leaves half a picture where the user asked
  // for one, nor writes through a link there.
  auto drawn = core::read_regular_file(picture.string(), kMaxPictureBytes);
  if (!drawn) return {RenderStatus::Io, drawn.error().message, {}, {}};
  if (auto w = core::write_file_atomically(o.output.string(), drawn.value()); !w) {
    return {RenderStatus::Io, w.error().message, {}, {}};
  }
  return r;
}

}  // namespace

Rendered render(const MissionPlot& plot, const RenderOptions& options) {
  std::string pattern = (fs::temp_directory_path() / "strata-plot-XXXXXX").string();
  if (!mkdtemp(pattern.data())) {
    return {RenderStatus::Io, fmt::format("cannot make a temporary folder: {}", std::strerror(errno)), {}, {}};
  }
  const fs::path folder = pattern;
  Rendered r = render_in(plot, options, folder);
  if (options.keep_folder) {
    r.kept_folder = folder;
  } else {
    std::error_code ec;
    fs::remove_all(folder, ec);
  }
  return r;
}

}  // namespace strata::plot
