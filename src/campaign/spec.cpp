#include "campaign/spec.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <string>

#include <fmt/format.h>

#include "campaign/axis.h"
#include "campaign/spec_files.h"
#include "campaign/spec_perturb.h"
#include "core/file.h"
#include "core/mission_language.h"
#include "core/toml_reader.h"
#include "run/answers.h"
#include "vehicle/scenario.h"

namespace strata::campaign {
namespace {

namespace fs = std::filesystem;

std::uint64_t sat_add(std::uint64_t a, std::uint64_t b) { return b > kSaturated - a ? kSaturated : a + b; }

const std::vector<std::pair<std::string_view, vehicle::FaultKind>> kFaultKinds = {
    {"weak_thrusters", vehicle::FaultKind::WeakThrusters},
    {"leak", vehicle::FaultKind::Leak},
    {"sensor_dropout", vehicle::FaultKind::SensorDropout},
    {"link_loss", vehicle::FaultKind::LinkLoss},
};

bool needs_duration(vehicle::FaultKind k) {
  return k == vehicle::FaultKind::SensorDropout || k == vehicle::FaultKind::LinkLoss;
}

class SpecReader {
 public:
  SpecReader(const std::string& path, const SpecLimits& limits) : errors_(path), limits_(limits) { spec_.path = path; }

  core::Result<Spec> read(const toml::table& root) {
    for (auto&& [key, node] : root) {
      static constexpr std::string_view kKeys[] = {"name",           "description",  "missions", "seeds",
                                                   "sample_seed",    "params",       "world",    "perturb",
                                                   "max_sim_time_s", "telemetry_hz", "expect",   "family"};
      if (std::find(std::begin(kKeys), std::end(kKeys), key.str()) == std::end(kKeys)) {
        errors_.add(key,
                    fmt::format("unknown key '{}' (expected name, description, missions, seeds, sample_seed, "
                                "params, world, perturb, max_sim_time_s, telemetry_hz, [expect.NAME] or [[family]])",
                                key.str()));
      }
    }
    if (const toml::node* n = root.get("name")) {
      if (auto s = n->value<std::string>())
        spec_.name = *s;
      else
        errors_.add(*n, "'name' must be a string");
    }
    if (const toml::node* n = root.get("description"); n && !n->is_string()) {
      errors_.add(*n, "'description' must be a string");
    }
    if (const toml::node* n = root.get("sample_seed")) {
      const auto* i = n->as_integer();
      if (i == nullptr || i->get() < 0)
        errors_.add(*n, "'sample_seed' must be an integer >= 0");
      else
        spec_.sample_seed = static_cast<std::uint64_t>(i->get());
    }
    if (const toml::node* n = root.get("max_sim_time_s")) {
      auto v = core::toml_number(*n);
      if (!v || !std::isfinite(*v) || *v < 1.0 || *v > kMaxSimTimeLimitS) {
        errors_.add(*n, fmt::format("'max_sim_time_s' must be a number in [1, {}]", kMaxSimTimeLimitS));
      } else {
        spec_.max_sim_time_s = *v;
      }
    }
    if (const toml::node* n = root.get("telemetry_hz")) {
      auto v = core::toml_number(*n);
      if (!v || !std::isfinite(*v) || *v < 0.1 || *v > 100.0) {
        errors_.add(*n, "'telemetry_hz' must be a number in [0.1, 100]");
      } else {
        spec_.telemetry_hz = *v;
      }
    }
    read_missions(root);
    read_seeds(root);
    read_expectations(root);
    read_params(errors_, root, spec_);
    read_world(errors_, root, spec_);
    if (const toml::node* n = root.get("perturb")) {
      spec_perturb_ = read_perturb(errors_, *n, "perturb", spec_.sample_seed, limits_.max_cases);
    }
    read_families(root);
    if (!errors_.empty()) return errors_.error();
    const std::uint64_t n = spec_.case_count();
    if (n > limits_.max_cases) {
      errors_.add(root.get("family") ? root.get("family")->source() : root.source(),
                  fmt::format("the spec makes {} cases, over the limit of {} (--max-cases raises it)",
                              n == kSaturated ? std::string("more than 2^64") : std::to_string(n), limits_.max_cases));
      return errors_.error();
    }
    return std::move(spec_);
  }

 private:
  void read_missions(const toml::table& root) {
    const toml::node* n = root.get("missions");
    if (n == nullptr) {
      errors_.add(root.source(), "missing 'missions' (a list of .coral or .pl files, relative to the spec)");
      return;
    }
    const toml::array* a = n->as_array();
    if (a == nullptr || a->empty()) {
      errors_.add(*n, "'missions' must be a non-empty list of paths");
      return;
    }
    const fs::path base = fs::path(spec_.path).parent_path();
    for (const toml::node& item : *a) {
      auto text = item.value<std::string>();
      if (!text || text->empty()) {
        errors_.add(item, "a mission must be a path (a string)");
        continue;
      }
      Mission m;
      m.path = *text;
      const fs::path p(*text);
      m.resolved = (p.is_absolute() || base.empty() ? p : base / p).lexically_normal().string();
      if (const auto language = core::mission_language(*text); language == core::MissionLanguage::Coral) {
        m.kind = MissionKind::Coral;
      } else if (language == core::MissionLanguage::Prolog) {
        m.kind = MissionKind::Prolog;
      } else {
        errors_.add(item, fmt::format("mission '{}' is neither CORAL (.coral) nor PROLOG (.pl)", *text));
        continue;
      }
      std::error_code ec;
      if (!fs::is_regular_file(m.resolved, ec)) {
        errors_.add(item, fmt::format("mission '{}' not found (looked for {})", *text, m.resolved));
        continue;
      }
      spec_.missions.push_back(std::move(m));
    }
  }

  void read_seeds(const toml::table& root) {
    const toml::node* n = root.get("seeds");
    if (n == nullptr) {
      spec_.seeds = {1};
      return;
    }
    if (const toml::array* a = n->as_array()) {
      if (a->empty() || a->size() > limits_.max_cases) {
        errors_.add(*n, fmt::format("'seeds' must list 1 to {} seeds", limits_.max_cases));
        return;
      }
      for (const toml::node& item : *a) {
        const auto* i = item.as_integer();
        if (i == nullptr || i->get() < 0)
          errors_.add(item, "a seed must be an integer >= 0");
        else
          spec_.seeds.push_back(static_cast<std::uint64_t>(i->get()));
      }
      return;
    }
    const toml::table* t = n->as_table();
    const toml::node* from = t ? t->get("from") : nullptr;
    const toml::node* count = t ? t->get("count") : nullptr;
    if (t == nullptr || from == nullptr || count == nullptr || t->size() != 2) {
      errors_.add(*n, "'seeds' must be a list of integers or { from = S, count = N }");
      return;
    }
    const auto* f = from->as_integer();
    const auto* c = count->as_integer();
    if (f == nullptr || f->get() < 0) errors_.add(*from, "'seeds.from' must be an integer >= 0");
    if (c == nullptr || c->get() < 1 || static_cast<std::uint64_t>(c->get()) > limits_.max_cases) {
      errors_.add(*count, fmt::format("'seeds.count' must be an integer in [1, {}]", limits_.max_cases));
    }
    if (f == nullptr || f->get() < 0 || c == nullptr || c->get() < 1 ||
        static_cast<std::uint64_t>(c->get()) > limits_.max_cases) {
      return;
    }
    for (std::int64_t i = 0; i < c->get(); ++i) spec_.seeds.push_back(static_cast<std::uint64_t>(f->get() + i));
  }

  void read_expectations(const toml::table& root) {
    const toml::node* n = root.get("expect");
    if (n == nullptr) return;
    const toml::table* t = n->as_table();
    if (t == nullptr) {
      errors_.add(*n, "'expect' must hold tables: [expect.NAME]");
      return;
    }
    for (auto&& [key, node] : *t) {
      const toml::table* set = node.as_table();
      if (set == nullptr) {
        errors_.add(node, fmt::format("'expect.{}' must be a table", key.str()));
        continue;
      }
      spec_.expectations[std::string(key.str())] = read_expectation(std::string(key.str()), *set);
    }
  }

  ExpectationSet read_expectation(const std::string& name, const toml::table& t) {
    ExpectationSet e;
    e.name = name;
    for (auto&& [key, node] : t) {
      const std::string_view k = key.str();
      if (k == "outcomes") {
        const toml::array* a = node.as_array();
        if (a == nullptr) {
          errors_.add(node, "'outcomes' must be a list: completed, aborted, failed");
          continue;
        }
        for (const toml::node& item : *a) {
          auto s = item.value<std::string>();
          if (!s || !known_outcome(*s)) {
            errors_.add(item, "an outcome is one of \"completed\", \"aborted\", \"failed\"");
          } else {
            e.outcomes.push_back(*s);
          }
        }
      } else if (k == "surface_within_s" || k == "max_depth_m") {
        auto v = core::toml_number(node);
        if (!v || !std::isfinite(*v) || *v < 0.0) {
          errors_.add(node, fmt::format("'{}' must be a number >= 0", k));
          continue;
        }
        (k == "surface_within_s" ? e.surface_within_s : e.max_depth_m) = *v;
      } else if (k == "guard") {
        auto s = node.value<std::string>();
        if (!s || !node.is_string() || s->empty()) {
          errors_.add(node, "'guard' must be the name of a guard of the mission, in quotes");
          continue;
        }
        e.guard = *s;
      } else if (k == "guard_within_s") {
        auto v = core::toml_number(node);
        if (!v || !std::isfinite(*v) || *v < 0.0) {
          errors_.add(node, "'guard_within_s' must be a number >= 0");
          continue;
        }
        e.guard_within_s = *v;
        if (!t.contains("guard")) errors_.add(node, "'guard_within_s' needs 'guard': the guard that must trip");
      } else if (k == "bound") {
        read_bound(node, e);
      } else if (k == "no_stall" || k == "no_refused_exec") {
        auto b = node.value<bool>();
        if (!b || !node.is_boolean()) {
          errors_.add(node, fmt::format("'{}' must be true or false", k));
          continue;
        }
        (k == "no_stall" ? e.no_stall : e.no_refused_exec) = *b;
      } else {
        errors_.add(key, fmt::format("unknown expectation '{}' (expected outcomes, surface_within_s, max_depth_m, "
                                     "no_stall, no_refused_exec, guard, guard_within_s, bound)",
                                     k));
      }
    }
    return e;
  }

  // `bound = "fault ASK -> TO"`: the question of `strata verify --bound`,
  // from the case's fault (the only event a campaign places in time).
  void read_bound(const toml::node& node, ExpectationSet& e) {
    auto s = node.value<std::string>();
    if (!s || !node.is_string()) {
      errors_.add(node, "'bound' must be a question in quotes: \"fault system_problem -> exec surface\"");
      return;
    }
    auto q = coral::parse_bound(*s);
    if (!q) {
      errors_.add(node, fmt::format("'bound': {}", q.error().message));
      return;
    }
    if (q.value().from != coral::BoundQuery::From::Fault) {
      errors_.add(node, "'bound' starts at the case's fault: \"fault ASK -> ...\" (the ask the fault turns to 1)");
      return;
    }
    if (!bound_texts_.contains(q.value().text) && bound_texts_.size() >= kMaxBounds) {
      if (bound_texts_.size() > kMaxBounds) return;  // said once, at the first
      bound_texts_.insert(q.value().text);
      errors_.add(node, fmt::format("more than {} different bounds in one spec (each is a timing analysis of every "
                                    "mission before the cases)",
                                    kMaxBounds));
      return;
    }
    bound_texts_.insert(q.value().text);
    e.bound = std::move(q).value();
  }

  void read_families(const toml::table& root) {
    const toml::node* n = root.get("family");
    if (n == nullptr) {
      errors_.add(root.source(), "missing [[family]]: at least one fault family (fault = \"none\" for nominal runs)");
      return;
    }
    const toml::array* a = n->as_array();
    if (a == nullptr || a->empty() || !a->is_array_of_tables()) {
      errors_.add(*n, "'family' must be an array of tables ([[family]])");
      return;
    }
    for (const toml::node& item : *a) read_family(*item.as_table());
  }

  void read_family(const toml::table& t) {
    Family f;
    for (auto&& [key, node] : t) {
      static constexpr std::string_view kKeys[] = {"name",    "fault",  "at_s",     "health",  "duration_s",
                                                   "forever", "expect", "missions", "answers", "perturb"};
      if (std::find(std::begin(kKeys), std::end(kKeys), key.str()) == std::end(kKeys)) {
        errors_.add(key, fmt::format("unknown key '{}' in a family (expected name, fault, at_s, health, duration_s, "
                                     "forever, expect, missions, answers, perturb)",
                                     key.str()));
      }
    }
    const toml::node* fault = t.get("fault");
    auto fault_text = fault ? fault->value<std::string>() : std::nullopt;
    if (!fault_text) {
      errors_.add(fault ? fault->source() : t.source(), "a family needs 'fault': a fault kind, or \"none\"");
      return;
    }
    if (*fault_text != "none") {
      auto it = std::find_if(kFaultKinds.begin(), kFaultKinds.end(), [&](auto& p) { return p.first == *fault_text; });
      if (it == kFaultKinds.end()) {
        errors_.add(*fault, fmt::format("unknown fault kind '{}' (expected weak_thrusters, leak, sensor_dropout, "
                                        "link_loss or none)",
                                        *fault_text));
        return;
      }
      f.fault = it->second;
    }
    f.name = *fault_text;
    if (const toml::node* n = t.get("name")) {
      auto s = n->value<std::string>();
      if (!s || s->empty())
        errors_.add(*n, "'name' must be a non-empty string");
      else
        f.name = *s;
    }
    if (std::any_of(spec_.families.begin(), spec_.families.end(), [&](const Family& g) { return g.name == f.name; })) {
      errors_.add(t.get("name") ? t.get("name")->source() : t.source(),
                  fmt::format("a second family named '{}' (give each a distinct 'name')", f.name));
    }
    f.expect = "default";
    if (const toml::node* n = t.get("expect")) {
      auto s = n->value<std::string>();
      if (!s)
        errors_.add(*n, "'expect' must name an [expect.NAME] table");
      else if (!spec_.expectations.contains(*s))
        errors_.add(*n, fmt::format("no [expect.{}] in this spec", *s));
      else
        f.expect = *s;
    } else if (!spec_.expectations.contains("default")) {
      ExpectationSet any;  // nothing checked but that it ran
      any.name = "default";
      spec_.expectations["default"] = any;
    }
    read_axes(t, f);
    read_family_missions(t, f);
    read_answers(t, f);
    read_family_perturb(errors_, t, f, spec_perturb_, spec_.base_params, spec_.sample_seed, limits_.max_cases);
    spec_.families.push_back(std::move(f));
  }

  // missions = [...]: the family runs for these of the spec's missions only.
  void read_family_missions(const toml::table& t, Family& f) {
    const toml::node* n = t.get("missions");
    if (n == nullptr) return;
    const toml::array* a = n->as_array();
    if (a == nullptr || a->empty()) {
      errors_.add(*n, "a family's 'missions' must be a non-empty list of the spec's missions");
      return;
    }
    for (const toml::node& item : *a) {
      auto text = item.value<std::string>();
      auto it = text ? std::find_if(spec_.missions.begin(), spec_.missions.end(),
                                    [&](const Mission& m) { return m.path == *text; })
                     : spec_.missions.end();
      if (it == spec_.missions.end()) {
        errors_.add(item, "a family's mission must be one of the spec's 'missions', as written there");
        continue;
      }
      f.missions.push_back(static_cast<std::size_t>(it - spec_.missions.begin()));
    }
  }

  // answers = "FILE": read and parsed now, so a bad file is the spec's error;
  // checked against each mission when its case runs.
  void read_answers(const toml::table& t, Family& f) {
    const toml::node* n = t.get("answers");
    if (n == nullptr) return;
    auto text = n->value<std::string>();
    if (!text || text->empty()) {
      errors_.add(*n, "'answers' must be the path of an answers file (`strata verify --witness-out` writes one)");
      return;
    }
    const fs::path base = fs::path(spec_.path).parent_path();
    const fs::path p(*text);
    f.answers = *text;
    f.answers_resolved = (p.is_absolute() || base.empty() ? p : base / p).lexically_normal().string();
    auto bytes = core::read_regular_file(f.answers_resolved, run::kMaxAnswersFileBytes);
    auto script = bytes ? run::parse_answers(bytes.value(), *text) : core::Result<run::AnswerScript>(bytes.error());
    if (!script) {
      errors_.add(*n, fmt::format("answers '{}': {}", *text, script.error().message));
      return;
    }
    const bool names_nets = std::any_of(script.value().answers.begin(), script.value().answers.end(),
                                        [](const run::ScriptedAnswer& a) { return !a.net.empty(); });
    for (std::size_t m = 0; m < spec_.missions.size() && names_nets; ++m) {
      if (f.applies_to(m) && spec_.missions[m].kind == MissionKind::Prolog) {
        errors_.add(*n, fmt::format("answers '{}' name CORAL nets, and this family runs '{}' (PROLOG rules): give "
                                    "the family missions = [...]",
                                    *text, spec_.missions[m].path));
        return;
      }
    }
  }

  void read_axes(const toml::table& t, Family& f) {
    const toml::node* at = t.get("at_s");
    const toml::node* health = t.get("health");
    const toml::node* duration = t.get("duration_s");
    const toml::node* forever = t.get("forever");
    const auto kind = f.fault;
    auto refuse = [&](const toml::node* n, std::string_view key) {
      if (n != nullptr) errors_.add(*n, fmt::format("'{}' does not apply to a {} family", key, f.name));
    };
    if (!kind) {
      refuse(at, "at_s"), refuse(health, "health"), refuse(duration, "duration_s"), refuse(forever, "forever");
      return;
    }
    const std::uint64_t max = limits_.max_cases;
    if (at == nullptr) {
      errors_.add(t.source(), fmt::format("family '{}' needs 'at_s': when the fault starts", f.name));
    } else if (auto v = parse_axis(errors_, *at, {"at_s", 0.0, kMaxSimTimeLimitS, true, max}, spec_.sample_seed,
                                   f.name + ".at_s")) {
      f.at_s = std::move(*v);
    }
    if (*kind == vehicle::FaultKind::WeakThrusters) {
      if (health == nullptr) {
        errors_.add(t.source(), fmt::format("family '{}' needs 'health': the fraction of nominal thrust", f.name));
      } else if (auto v = parse_axis(errors_, *health, {"health", 0.0, 1.0, true, max}, spec_.sample_seed,
                                     f.name + ".health")) {
        f.health = std::move(*v);
      }
    } else {
      refuse(health, "health");
    }
    if (!needs_duration(*kind)) {
      refuse(duration, "duration_s"), refuse(forever, "forever");
      return;
    }
    if (forever != nullptr) {
      if (*kind != vehicle::FaultKind::LinkLoss)
        refuse(forever, "forever");
      else if (!forever->is_boolean() || !*forever->value<bool>())
        errors_.add(*forever, "'forever' must be true");
      else if (duration != nullptr)
        errors_.add(*duration, "give either 'duration_s' or 'forever = true', not both");
      else
        f.forever = true;
      return;
    }
    if (duration == nullptr) {
      errors_.add(t.source(), fmt::format("family '{}' needs 'duration_s'{}", f.name,
                                          *kind == vehicle::FaultKind::LinkLoss ? " or 'forever = true'" : ""));
    } else if (auto v = parse_axis(errors_, *duration, {"duration_s", 0.0, kMaxSimTimeLimitS, false, max},
                                   spec_.sample_seed, f.name + ".duration_s")) {
      f.duration_s = std::move(*v);
    }
  }

  core::TomlErrors errors_;
  std::set<std::string> bound_texts_;  // the distinct `bound` questions read so far
  SpecLimits limits_;
  Spec spec_;
  std::vector<Perturbation> spec_perturb_;  // the top-level perturb, for every family
};

}  // namespace

std::uint64_t Family::combinations() const {
  std::uint64_t n = 1;
  for (const Perturbation& p : perturb) n = sat_mul(n, p.values.size());
  if (!fault) return n;
  n = sat_mul(n, at_s.size());
  if (!health.empty()) n = sat_mul(n, health.size());
  if (!duration_s.empty()) n = sat_mul(n, duration_s.size());
  return n;
}

std::uint64_t Spec::combinations_for(std::size_t mission) const {
  std::uint64_t n = 0;
  for (const Family& f : families) {
    if (f.applies_to(mission)) n = sat_add(n, f.combinations());
  }
  return n;
}

std::uint64_t Spec::case_count() const {
  std::uint64_t n = 0;
  for (std::size_t m = 0; m < missions.size(); ++m) n = sat_add(n, combinations_for(m));
  return sat_mul(n, seeds.size());
}

bool known_outcome(std::string_view outcome) {
  return outcome == "completed" || outcome == "aborted" || outcome == "failed";
}

core::Result<Spec> parse_spec(std::string_view text, const std::string& path, const SpecLimits& limits) {
  auto table = core::parse_toml(text, path);
  if (!table) return table.error();
  return SpecReader(path, limits).read(table.value());
}

core::Result<Spec> load_spec(const std::string& path, const SpecLimits& limits) {
  auto text = core::read_toml_text(path);
  if (!text) return text.error();
  return parse_spec(text.value(), path, limits);
}

}  // namespace strata::campaign
