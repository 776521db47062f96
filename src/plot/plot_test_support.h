#pragma once
// What plot_test.cpp and track_test.cpp share: the fixtures, a temporary
// folder, and an SVG drawn by gnuplot read back as curves and texts.
#include <stdlib.h>

#include <algorithm>
#include <filesystem>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <pugixml.hpp>

#include "plot/gnuplot.h"
#include "plot/plot_log.h"

namespace strata::plot::testing {

namespace fs = std::filesystem;

inline std::string fixture(const char* name) { return std::string(STRATA_SOURCE_DIR) + "/tests/plot/" + name; }

// A log given as text, read as from a file named x.jsonl.
inline core::Result<MissionPlot> read_text(const std::string& text) {
  std::istringstream in(text);
  return read_log(in, "x.jsonl");
}

inline MissionPlot read_fixture(const char* name) {
  auto r = read_log_file(fixture(name));
  if (!r) ADD_FAILURE() << r.error().message;
  return r ? r.value() : MissionPlot{};
}

class TempDir {
 public:
  TempDir() {
    std::string pattern = (fs::temp_directory_path() / "plot_test-XXXXXX").string();
    path_ = mkdtemp(pattern.data());
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// The points of each subpath of an SVG path's d (gnuplot writes only M and L).
inline std::vector<std::vector<std::pair<double, double>>> subpaths(const std::string& d) {
  std::vector<std::vector<std::pair<double, double>>> out;
  std::istringstream in(d);
  char command = 0;
  while (in >> command) {
    if (command != 'M' && command != 'L') continue;
    double x = 0, y = 0;
    char comma = 0;
    if (!(in >> x >> comma >> y)) break;
    if (command == 'M' || out.empty()) out.emplace_back();
    out.back().emplace_back(x, y);
  }
  return out;
}

struct Svg {
  pugi::xml_document doc;
  std::vector<std::string> texts;
  // A plotted curve's points, by the title in its key.
  std::vector<std::vector<std::pair<double, double>>> curve(const std::string& title) const {
    for (auto g : doc.select_nodes("//*[local-name()='g'][starts-with(@id, 'gnuplot_plot_')]")) {
      const auto key = g.node().select_node(".//*[local-name()='text']");
      if (!key || key.node().child_value() != title) continue;
      const auto path = g.node().select_node(".//*[local-name()='path']");
      if (path) return subpaths(path.node().attribute("d").value());
    }
    return {};
  }
  bool has_text(const std::string& t) const { return std::find(texts.begin(), texts.end(), t) != texts.end(); }
};

// Draws a fixture into an SVG and parses it.
inline bool draw(const char* name, Svg& svg, TempDir& dir) {
  const fs::path out = dir.path() / "out.svg";
  Rendered r = render(read_fixture(name), {Format::Svg, out});
  EXPECT_TRUE(r.ok()) << r.message;
  auto parsed = svg.doc.load_file(out.c_str());
  EXPECT_TRUE(parsed) << parsed.description();
  for (auto t : svg.doc.select_nodes("//*[local-name()='text']")) svg.texts.emplace_back(t.node().child_value());
  return r.ok() && parsed;
}

#define SKIP_WITHOUT_GNUPLOT() \
  if (!find_on_path("gnuplot")) GTEST_SKIP() << "gnuplot is not on PATH (Debian: apt-get install gnuplot-nox)"

}  // namespace strata::plot::testing
