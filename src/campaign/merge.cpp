#include "campaign/merge.h"

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <map>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "campaign/output.h"
#include "campaign/report_html.h"
#include "campaign/summary.h"
#include "core/file.h"

namespace strata::campaign {
namespace {

namespace fs = std::filesystem;
constexpr std::size_t kMaxLogBytes = std::size_t{256} << 20;

// A file a line names ("logs/case-3.jsonl") copied from one folder to the other.
core::Result<void> copy_named(const std::string& from_dir, const std::string& to_dir, const std::string& name) {
  if (name.find("..") != std::string::npos || fs::path(name).is_absolute()) {
    return core::make_error(core::ErrorCode::InvalidInput, fmt::format("{}: a file name outside the folder", name));
  }
  auto bytes = core::read_regular_file((fs::path(from_dir) / name).string(), kMaxLogBytes);
  if (!bytes) return bytes.error();
  return write_out_file(to_dir, name, bytes.value());
}

}  // namespace

core::Result<MergeOutcome> merge_campaigns(const Spec& spec, const std::vector<std::string>& dirs,
                                           const std::string& out_dir, const std::string& command) {
  std::map<std::uint64_t, std::pair<nlohmann::ordered_json, std::string>> cases;  // index -> line, its folder
  MergeOutcome out;
  double wall_s = 0.0;
  for (const std::string& dir : dirs) {
    const std::string path = (fs::path(dir) / "results.jsonl").string();
    auto text = core::read_regular_file(path, kMaxResultsBytes);
    if (!text) return text.error();
    std::istringstream in(text.value());
    std::string line;
    for (std::size_t n = 1; std::getline(in, line); ++n) {
      if (line.empty()) continue;
      auto j = nlohmann::ordered_json::parse(line, nullptr, false);
      if (j.is_discarded() || !j.contains("index") || !j["index"].is_number_unsigned() || !j.contains("inputs")) {
        return core::make_error(core::ErrorCode::InvalidInput,
                                fmt::format("{}:{}: not a line of a campaign's results.jsonl", path, n));
      }
      const auto index = j["index"].get<std::uint64_t>();
      if (index >= spec.case_count()) {
        return core::make_error(core::ErrorCode::InvalidInput, fmt::format("{}:{}: case {} is not in {} (0-{})", path,
                                                                           n, index, spec.path, spec.case_count() - 1));
      }
      if (cases.contains(index)) {
        ++out.duplicates;
        continue;
      }
      cases.emplace(index, std::pair{std::move(j), dir});
    }
    // The shards ran side by side: the merged run took as long as the longest.
    auto report = core::read_regular_file((fs::path(dir) / "report.json").string(), kMaxResultsBytes);
    if (report) {
      auto r = nlohmann::json::parse(report.value(), nullptr, false);
      if (!r.is_discarded() && r.contains("timings")) wall_s = std::max(wall_s, r["timings"].value("wall_s", 0.0));
    }
  }
  if (auto r = prepare_out_dir(out_dir); !r) return r.error();
  auto results = ResultsFile::create(out_dir);
  if (!results) return results.error();
  Summary summary(spec);
  for (const Mission& m : spec.missions) {
    if (m.kind != MissionKind::Coral) continue;
    if (auto names = mission_transitions(m.resolved)) summary.set_transitions(m.path, std::move(names).value());
  }
  for (auto& [index, entry] : cases) {
    auto& [line, dir] = entry;
    for (const char* key : {"log", "scenario", "params_file"}) {
      if (line.contains(key) && !copy_named(dir, out_dir, line[key].get<std::string>())) line.erase(key);
    }
    if (line.contains("repro_run")) {
      // The copied scenario (and parameter file), not the shard's.
      std::string repro = line["repro_run"].get<std::string>();
      for (auto at = repro.find(dir + "/"); at != std::string::npos; at = repro.find(dir + "/", at + out_dir.size())) {
        repro.replace(at, dir.size(), out_dir);
      }
      line["repro_run"] = repro;
    }
    summary.add(line);
    if (auto r = results.value().append(line); !r) return r.error();
  }
  out.planned = spec.case_count();
  out.done = summary.done();
  out.failed = summary.failed();
  CampaignRun run{out.planned, static_cast<int>(dirs.size()), wall_s, out.done < out.planned, command};
  const nlohmann::ordered_json report = summary.to_json(run);
  if (auto r = write_out_file(out_dir, "report.json", report.dump(2) + "\n"); !r) return r.error();
  if (auto r = write_out_file(out_dir, "report.html", report_html(report)); !r) return r.error();
  return out;
}

core::Result<std::vector<std::uint64_t>> shard_indices(const std::string& text, std::uint64_t count) {
  const auto slash = text.find('/');
  std::uint64_t shard = 0, n = 0;
  const auto parse = [](std::string_view s, std::uint64_t& v) {
    auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    return ec == std::errc() && end == s.data() + s.size() && !s.empty();
  };
  if (slash == std::string::npos || !parse(std::string_view(text).substr(0, slash), shard) ||
      !parse(std::string_view(text).substr(slash + 1), n) || n == 0 || shard >= n) {
    return core::make_error(
        core::ErrorCode::InvalidInput,
        fmt::format("--shard '{}': expected I/N with 0 <= I < N (every N-th case from the I-th)", text));
  }
  std::vector<std::uint64_t> indices;
  for (std::uint64_t i = shard; i < count; i += n) indices.push_back(i);
  return indices;
}

}  // namespace strata::campaign
