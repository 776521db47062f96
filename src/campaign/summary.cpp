#include "campaign/summary.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace strata::campaign {

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double rank = std::ceil(p / 100.0 * static_cast<double>(values.size()));
  const auto i = static_cast<std::size_t>(std::clamp(rank, 1.0, static_cast<double>(values.size()))) - 1;
  return values[i];
}

Summary::Summary(const Spec& spec) : spec_(spec) {
  for (const Mission& m : spec.missions) {
    for (const Family& f : spec.families) {
      Row row{m.path, f.name, {}, {}, {}};
      if (!f.fault || f.at_s.empty()) {
        row.labels = {"-"};
      } else {
        std::vector<double> at = f.at_s;
        std::sort(at.begin(), at.end());
        at.erase(std::unique(at.begin(), at.end()), at.end());
        if (at.size() <= kMaxMatrixColumns) {
          for (double t : at) {
            row.edges.push_back(t);
            row.labels.push_back(fmt::format("{:g}", t));
          }
        } else {
          const double lo = at.front(), hi = at.back();
          const double w = (hi - lo) / static_cast<double>(kMaxMatrixColumns);
          for (std::size_t c = 0; c < kMaxMatrixColumns; ++c) {
            const double a = lo + w * static_cast<double>(c);
            row.edges.push_back(a);
            row.labels.push_back(fmt::format("{:.3g}–{:.3g}", a, a + w));
          }
        }
      }
      row.cells.resize(row.labels.size());
      rows_.push_back(std::move(row));
    }
  }
  for (const Family& f : spec.families) {
    surfacing_[f.name].limit_s = spec.expectations.at(f.expect).surface_within_s;
  }
}

std::uint64_t Summary::past_proven_bound() const {
  std::uint64_t n = 0;
  for (const auto& [key, b] : bounds_) n += b.exceeded;
  return n;
}

void Summary::set_transitions(const std::string& mission, std::vector<std::string> transitions) {
  transitions_[mission] = std::move(transitions);
}

std::size_t Summary::column(const Row& row, double at_s) const {
  if (row.edges.empty()) return 0;
  auto it = std::upper_bound(row.edges.begin(), row.edges.end(), at_s + 1e-9);
  return it == row.edges.begin() ? 0 : static_cast<std::size_t>(it - row.edges.begin()) - 1;
}

void Summary::add(const nlohmann::ordered_json& line) {
  ++done_;
  const bool pass = line.value("pass", false);
  pass ? ++passed_ : ++failed_;
  const std::string outcome = line.value("outcome", "?");
  ++outcomes_[outcome];
  const auto& in = line["inputs"];
  const std::string mission = in.value("mission", "");
  const std::string family = in.value("family", "");
  auto& fam = families_[family];
  ++fam.first;
  if (!pass) ++fam.second;
  for (Row& row : rows_) {
    if (row.mission != mission || row.family != family) continue;
    const double at = in["fault"].value("at_s", 0.0);
    Cell& cell = row.cells[column(row, at)];
    ++cell.done;
    if (!pass) ++cell.failed;
    ++cell.outcomes[outcome];
  }
  for (const auto& check : line["checks"]) {
    if (check.value("name", "") != "bound") continue;
    BoundSeen& b = bounds_[{mission, family}];
    const bool proven = check.contains("limit") && check["limit"].is_number();  // no limit: no proof
    if (proven) {
      b.proven_s = check["limit"].get<double>();
    } else if (b.note.empty()) {
      b.note = check.value("note", "");
    }
    if (!proven && !check.value("pass", true)) ++b.unproven;
    if (check.contains("figure") && check["figure"].is_number()) {
      ++b.measured;
      b.max_s = std::max(b.max_s, check["figure"].get<double>());
    }
    if (proven && !check.value("pass", true)) ++b.exceeded;
  }
  for (const auto& check : line["checks"]) {
    if (check.value("name", "") != "surface_within_s") continue;
    Surfacing& s = surfacing_[family];
    if (check["figure"].is_number())
      s.times_s.push_back(check["figure"].get<double>());
    else if (!check.value("pass", true))
      ++s.never;
  }
  if (!pass) {
    if (failures_.size() < kMaxListedFailures) {
      nlohmann::ordered_json f;
      f["index"] = line["index"];
      f["inputs"] = in;
      f["outcome"] = outcome;
      f["reason"] = line.value("reason", "");
      nlohmann::ordered_json failed = nlohmann::ordered_json::array();
      for (const auto& check : line["checks"]) {
        if (!check.value("pass", true)) failed.push_back(check);
      }
      f["failed_checks"] = std::move(failed);
      for (const char* key : {"repro", "repro_run", "log", "log_note", "scenario"}) {
        if (line.contains(key)) f[key] = line[key];
      }
      failures_.push_back(std::move(f));
    }
  }
  if (line.contains("coverage")) {
    auto& cov = coverage_[mission];
    for (const auto& [kind, items] : line["coverage"].items()) {
      for (const auto& item : items) ++cov[kind + ":" + item.get<std::string>()];
    }
  }
  if (line.contains("timings") && line["timings"]["wall_s"].is_number()) {
    case_wall_s_.push_back(line["timings"]["wall_s"].get<double>());
  }
}

nlohmann::ordered_json Summary::to_json(const CampaignRun& run) const {
  nlohmann::ordered_json j;
  j["campaign"] = spec_.name.empty() ? spec_.path : spec_.name;
  j["spec"] = spec_.path;
  j["command"] = run.command;
  j["cases"] = {{"planned", run.planned}, {"done", done_}, {"passed", passed_}, {"failed", failed_}};
  j["interrupted"] = run.interrupted;
  j["outcomes"] = outcomes_;
  nlohmann::ordered_json fams = nlohmann::ordered_json::array();
  for (const Family& f : spec_.families) {
    auto it = families_.find(f.name);
    const auto counts = it == families_.end() ? std::pair<std::uint64_t, std::uint64_t>{0, 0} : it->second;
    fams.push_back({{"name", f.name},
                    {"fault", f.fault ? std::string(vehicle::to_string(*f.fault)) : std::string("none")},
                    {"expect", f.expect},
                    {"done", counts.first},
                    {"failed", counts.second}});
  }
  j["families"] = std::move(fams);
  nlohmann::ordered_json matrix = nlohmann::ordered_json::array();
  for (const Row& row : rows_) {
    nlohmann::ordered_json cells = nlohmann::ordered_json::array();
    for (std::size_t c = 0; c < row.cells.size(); ++c) {
      cells.push_back({{"at_s", row.labels[c]},
                       {"done", row.cells[c].done},
                       {"failed", row.cells[c].failed},
                       {"outcomes", row.cells[c].outcomes}});
    }
    matrix.push_back({{"mission", row.mission}, {"family", row.family}, {"cells", std::move(cells)}});
  }
  j["matrix"] = std::move(matrix);
  nlohmann::ordered_json surf = nlohmann::ordered_json::array();
  for (const Family& f : spec_.families) {
    const Surfacing& s = surfacing_.at(f.name);
    if (!s.limit_s) continue;
    nlohmann::ordered_json e{
        {"family", f.name}, {"limit_s", *s.limit_s}, {"measured", s.times_s.size()}, {"never_surfaced", s.never}};
    if (!s.times_s.empty()) {
      e["p50_s"] = percentile(s.times_s, 50);
      e["p90_s"] = percentile(s.times_s, 90);
      e["p99_s"] = percentile(s.times_s, 99);
      e["max_s"] = percentile(s.times_s, 100);
      e["over_limit"] = std::count_if(s.times_s.begin(), s.times_s.end(), [&](double t) { return t > *s.limit_s; });
      // Twenty bins from 0 to the larger of the limit and the slowest case.
      const double top = std::max(*s.limit_s, e["max_s"].get<double>()) * 1.0001 + 1e-9;
      std::vector<std::uint64_t> bins(20, 0);
      for (double t : s.times_s) ++bins[std::min<std::size_t>(19, static_cast<std::size_t>(t / top * 20.0))];
      e["histogram"] = {{"bin_s", top / 20.0}, {"counts", bins}};
    }
    surf.push_back(std::move(e));
  }
  j["time_to_surface"] = std::move(surf);
  // A case past the proven worst case is a failure of the analysis, not of
  // the mission: counted apart ("exceeded"), with the worst measured time.
  nlohmann::ordered_json bounds = nlohmann::ordered_json::array();
  for (const auto& [key, b] : bounds_) {
    const Family* f = nullptr;
    for (const Family& fam : spec_.families) {
      if (fam.name == key.second) f = &fam;
    }
    if (f == nullptr) continue;
    const ExpectationSet& set = spec_.expectations.at(f->expect);
    nlohmann::ordered_json e{{"mission", key.first},
                             {"family", key.second},
                             {"bound", set.bound ? set.bound->text : ""},
                             {"proven_s", b.proven_s ? nlohmann::ordered_json(*b.proven_s) : nullptr},
                             {"measured", b.measured},
                             {"max_s", b.measured ? nlohmann::ordered_json(b.max_s) : nullptr},
                             {"exceeded", b.exceeded},
                             {"unproven", b.unproven}};
    if (b.proven_s && b.measured && b.max_s > 0) e["ratio"] = std::round(*b.proven_s / b.max_s * 100.0) / 100.0;
    if (!b.note.empty()) e["note"] = b.note;
    bounds.push_back(std::move(e));
  }
  j["bounds"] = std::move(bounds);
  j["failures"] = failures_;
  j["failures_not_listed"] = failed_ > failures_.size() ? failed_ - failures_.size() : 0;
  nlohmann::ordered_json cov = nlohmann::ordered_json::object();
  for (const Mission& m : spec_.missions) {
    auto it = coverage_.find(m.path);
    nlohmann::ordered_json c;
    std::map<std::string, std::uint64_t> fired, answers, exits;
    if (it != coverage_.end()) {
      for (const auto& [item, n] : it->second) {
        const auto colon = item.find(':');
        const std::string kind = item.substr(0, colon), name = item.substr(colon + 1);
        (kind == "fired" ? fired : kind == "answers" ? answers : exits)[name] = n;
      }
    }
    c["fired"] = fired;
    if (auto t = transitions_.find(m.path); t != transitions_.end()) {
      std::vector<std::string> never;
      for (const std::string& name : t->second) {
        if (!fired.contains(name)) never.push_back(name);
      }
      c["transitions"] = t->second.size();
      c["never_fired"] = never;
    }
    c["answers"] = answers;
    c["exits"] = exits;
    cov[m.path] = std::move(c);
  }
  j["coverage"] = std::move(cov);
  const double rate = run.wall_s > 0 ? static_cast<double>(done_) / run.wall_s : 0.0;
  j["timings"] = {{"wall_s", run.wall_s},
                  {"workers", run.workers},
                  {"cases_per_s", rate},
                  {"case_wall_p50_s", percentile(case_wall_s_, 50)},
                  {"case_wall_max_s", percentile(case_wall_s_, 100)}};
  return j;
}

}  // namespace strata::campaign
