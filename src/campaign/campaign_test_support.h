#pragma once
// Test support for the campaign tests: a fresh temp folder, files written
// into it, and the tank mission's path.
#include <stdlib.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "campaign/spec.h"

namespace strata::campaign::testing {

namespace fs = std::filesystem;

inline const std::string kTankDir = std::string(STRATA_SOURCE_DIR) + "/missions/tank";

class TempDir {
 public:
  TempDir() {
    std::string pattern = (fs::path(::testing::TempDir()) / "strata_campaign_XXXXXX").string();
    if (char* made = mkdtemp(pattern.data())) path_ = made;
    EXPECT_FALSE(path_.empty()) << "mkdtemp failed for " << pattern;
  }
  ~TempDir() {
    std::error_code ec;
    if (!path_.empty()) fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  std::string path() const { return path_.string(); }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(file(name)) << text;
    return file(name);
  }

 private:
  fs::path path_;
};

inline std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// results.jsonl's lines, parsed; a line that is not JSON fails the test.
inline std::vector<nlohmann::json> read_results(const std::string& path) {
  std::vector<nlohmann::json> lines;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    auto j = nlohmann::json::parse(line, nullptr, false);
    EXPECT_FALSE(j.is_discarded()) << "not JSON: " << line;
    if (!j.is_discarded()) lines.push_back(std::move(j));
  }
  return lines;
}

// Result lines by index, without what depends on the wall clock or the
// process (timings; repro_run names the output folder).
inline std::vector<nlohmann::json> by_index(std::vector<nlohmann::json> lines) {
  for (auto& l : lines) {
    l.erase("timings");
    l.erase("repro_run");
  }
  std::sort(lines.begin(), lines.end(), [](auto& a, auto& b) { return a["index"] < b["index"]; });
  return lines;
}

// A spec in a folder beside the tank mission's files (by absolute path).
inline std::string spec_text(const std::string& body) {
  return "missions = [\"" + kTankDir + "/tank.coral\"]\n" + body;
}

inline core::Result<Spec> parse(const std::string& text, const SpecLimits& limits = {}) {
  return parse_spec(text, "c.toml", limits);
}

inline std::string error_of(const std::string& text, const SpecLimits& limits = {}) {
  auto spec = parse(text, limits);
  EXPECT_FALSE(spec.ok()) << "the spec was accepted:\n" << text;
  return spec ? std::string() : spec.error().message;
}

}  // namespace strata::campaign::testing
