#include "campaign/compare.h"

#include <cmath>
#include <map>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "campaign/output.h"
#include "core/file.h"

namespace strata::campaign {
namespace {

using ResultLine = nlohmann::json;

// Inputs as text (keys sorted by nlohmann::json) -> the case's line.
core::Result<std::map<std::string, ResultLine>> read_results(const std::string& path) {
  auto text = core::read_regular_file(path, kMaxResultsBytes);
  if (!text) return text.error();
  std::map<std::string, ResultLine> cases;
  std::istringstream in(text.value());
  std::string line;
  for (std::size_t n = 1; std::getline(in, line); ++n) {
    if (line.empty()) continue;
    ResultLine j = ResultLine::parse(line, nullptr, false);
    if (j.is_discarded() || !j.is_object() || !j.contains("inputs") || !j.contains("pass") || !j.contains("index")) {
      return core::make_error(core::ErrorCode::InvalidInput,
                              fmt::format("{}:{}: not a line of a campaign's results.jsonl", path, n));
    }
    std::string key = j["inputs"].dump();
    cases.insert_or_assign(std::move(key), std::move(j));
  }
  return cases;
}

std::string name(const ResultLine& j) {
  const ResultLine& in = j["inputs"];
  std::string fault;
  for (const auto& [k, v] : in["fault"].items()) {
    if (k != "kind") fault += fmt::format(" {}={}", k, v.dump());
  }
  if (in.contains("params")) {
    for (const auto& [k, v] : in["params"].items()) fault += fmt::format(" {}={}", k, v.dump());
  }
  return fmt::format("{} · {} · {}{} · seed {}", in.value("mission", ""), in.value("family", ""),
                     in["fault"].value("kind", ""), fault, in.value("seed", 0));
}

std::string failed_checks(const ResultLine& j) {
  std::string out;
  for (const ResultLine& c : j["checks"]) {
    if (!c.value("pass", true))
      out += fmt::format("{}{} {}", out.empty() ? "" : ", ", c.value("name", ""), c["figure"].dump());
  }
  return out;
}

}  // namespace

core::Result<CompareReport> compare_results(const std::string& a_path, const std::string& b_path) {
  auto a = read_results(a_path);
  if (!a) return a.error();
  auto b = read_results(b_path);
  if (!b) return b.error();
  CompareReport r;
  for (const auto& [key, x] : a.value()) {
    auto it = b.value().find(key);
    if (it == b.value().end()) {
      r.only_a.push_back(fmt::format("{}: {}", x["index"].dump(), name(x)));
      continue;
    }
    const ResultLine& y = it->second;
    ++r.matched;
    const std::string label = fmt::format("{} -> {}: {}", x["index"].dump(), y["index"].dump(), name(x));
    const bool pa = x["pass"].get<bool>(), pb = y["pass"].get<bool>();
    if (pa && !pb)
      r.newly_failing.push_back(fmt::format("{} ({}; {})", label, y.value("outcome", ""), failed_checks(y)));
    if (!pa && pb)
      r.newly_passing.push_back(fmt::format("{} (was {}; {})", label, x.value("outcome", ""), failed_checks(x)));
    if (x.value("outcome", "") != y.value("outcome", "")) {
      r.outcome_changed.push_back(fmt::format("{}: {} -> {}", label, x.value("outcome", ""), y.value("outcome", "")));
    }
    if (pa == pb) {
      // The same verdict, a different figure: how far each moved.
      std::map<std::string, ResultLine> before;
      for (const ResultLine& c : x["checks"]) before[c.value("name", "")] = c["figure"];
      for (const ResultLine& c : y["checks"]) {
        auto b_it = before.find(c.value("name", ""));
        if (b_it == before.end() || b_it->second == c["figure"]) continue;
        if (b_it->second.is_number() && c["figure"].is_number() &&
            std::abs(b_it->second.get<double>() - c["figure"].get<double>()) < 1e-9) {
          continue;
        }
        r.figure_changed.push_back(
            fmt::format("{}: {} {} -> {}", label, c.value("name", ""), b_it->second.dump(), c["figure"].dump()));
      }
    }
  }
  for (const auto& [key, y] : b.value()) {
    if (!a.value().contains(key)) r.only_b.push_back(fmt::format("{}: {}", y["index"].dump(), name(y)));
  }
  return r;
}

std::string compare_text(const CompareReport& r, const std::string& a_path, const std::string& b_path) {
  std::string out = fmt::format(
      "A {}\nB {}\n{} cases in both; {} newly failing, {} newly passing, {} with another "
      "outcome, {} with another figure; {} only in A, {} only in B\n",
      a_path, b_path, r.matched, r.newly_failing.size(), r.newly_passing.size(), r.outcome_changed.size(),
      r.figure_changed.size(), r.only_a.size(), r.only_b.size());
  const auto section = [&out](const char* title, const std::vector<std::string>& lines) {
    if (lines.empty()) return;
    out += fmt::format("{}:\n", title);
    for (const auto& l : lines) out += "  " + l + "\n";
  };
  section("newly failing", r.newly_failing);
  section("newly passing", r.newly_passing);
  section("outcome changed", r.outcome_changed);
  section("figure changed", r.figure_changed);
  section("only in A", r.only_a);
  section("only in B", r.only_b);
  return out;
}

}  // namespace strata::campaign
