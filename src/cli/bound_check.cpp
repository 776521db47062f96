#include "cli/bound_check.h"

#include <cctype>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <streambuf>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/mission_run.h"
#include "cli/verify_bound.h"
#include "run/bound_options.h"
#include "run/coral_load.h"
#include "tactical/catalogue.h"

namespace strata::cli {
namespace {

class NullBuf : public std::streambuf {
 protected:
  int_type overflow(int_type c) override { return traits_type::not_eof(c); }
  std::streamsize xsputn(const char*, std::streamsize n) override { return n; }
};

bool is_to(const coral::BoundQuery& q, const nlohmann::json& request) {
  const std::string primitive = request.value("primitive", "");
  const std::string message = request.value("message", "");
  if (q.to == coral::BoundQuery::To::Surface) return primitive == "surface";
  if (primitive != q.to_name) return false;
  if (!q.to_verb) return true;
  std::string verb(coral::tactic_type_name(*q.to_verb));  // "EXEC"
  for (char& c : verb) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return message.starts_with(verb + " ");
}

// The sim time of the first request for TO at or after `after_s`, or nullopt.
std::optional<double> first_to(const std::filesystem::path& log, const coral::BoundQuery& q, double after_s) {
  std::ifstream in(log);
  std::string line;
  while (std::getline(in, line)) {
    const auto j = nlohmann::json::parse(line, nullptr, false);
    if (j.is_discarded() || j.value("event", "") != "request") continue;
    const double t = j.value("sim_time", -1.0);
    if (t + 1e-9 >= after_s && is_to(q, j)) return t;
  }
  return std::nullopt;
}

}  // namespace

std::vector<MeasuredReaction> measure_reactions(const std::string& mission, const coral::BoundQuery& query,
                                                const std::string& fault_kind, const std::vector<double>& fault_times,
                                                const std::string& scenario_toml, const std::string& work_dir) {
  const std::filesystem::path dir(work_dir);
  NullBuf null;
  std::ostream out(&null);
  std::ostream err(&null);
  std::vector<MeasuredReaction> measured;
  for (std::size_t i = 0; i < fault_times.size(); ++i) {
    const double at = fault_times[i];
    std::ofstream(dir / "fault.toml") << fmt::format("{}\n[[fault]]\nkind = \"{}\"\nat_s = {}\n", scenario_toml,
                                                     fault_kind, at);
    RunOptions o;
    o.mission = mission;
    o.scenario = (dir / "fault.toml").string();
    o.log = (dir / "run.jsonl").string();
    RunReport report = run_mission(o, out, err);
    MeasuredReaction m;
    m.fault_s = at;
    m.exit_code = report.exit_code;
    if (auto t = first_to(dir / "run.jsonl", query, at)) m.reaction_s = *t - at;
    measured.push_back(m);
  }
  return measured;
}

coral::BoundAnswer prove_bound(const std::string& mission, const coral::BoundQuery& query, double depth_max_m) {
  const tactical::Catalogue& cat = tactical::Catalogue::builtin();
  run::CoralLoad load = run::load_coral_file(mission, cat);
  if (!load.program) {
    coral::BoundAnswer a;
    a.message = "the mission does not compile";
    return a;
  }
  return coral::analyse_bound(*load.program, query, run::bound_options(cat, depth_max_m));
}

}  // namespace strata::cli
