#include "campaign/spec.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include <fmt/format.h>

#include "campaign/axis.h"
#include "core/file.h"
#include "core/toml_reader.h"
#include "run/answers.h"
#include "vehicle/params.h"

namespace strata::campaign {
namespace {

namespace fs = std::filesystem;

constexpr std::uint64_t kSaturated = std::numeric_limits<std::uint64_t>::max();

std::uint64_t sat_mul(std::uint64_t a, std::uint64_t b) {
  if (a != 0 && b > kSaturated / a) return kSaturated;
  return a * b;
}
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
      static constexpr std::string_view kKeys[] = {"name",        "description",    "missions",     "seeds",
                                                   "sample_seed", "max_sim_time_s", "telemetry_hz", "perturb",
                                                   "expect",      "family"};
      if (std::find(std::begin(kKeys), std::end(kKeys), key.str()) == std::end(kKeys)) {
        errors_.add(key, fmt::format("unknown key '{}' (expected name, description, missions, seeds, sample_seed, "
                                     "max_sim_time_s, telemetry_hz, perturb, [expect.NAME] or [[family]])",
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
    if (const toml::node* n = root.get("perturb")) spec_perturb_ = read_perturb(*n, "perturb");
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
      if (p.extension() == ".coral") {
        m.kind = MissionKind::Coral;
      } else if (p.extension() == ".pl") {
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
      } else if (k == "no_stall" || k == "no_refused_exec") {
        auto b = node.value<bool>();
        if (!b || !node.is_boolean()) {
          errors_.add(node, fmt::format("'{}' must be true or false", k));
          continue;
        }
        (k == "no_stall" ? e.no_stall : e.no_refused_exec) = *b;
      } else {
        errors_.add(key, fmt::format("unknown expectation '{}' (expected outcomes, surface_within_s, max_depth_m, "
                                     "no_stall, no_refused_exec)",
                                     k));
      }
    }
    return e;
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
    read_family_perturb(t, f);
    spec_.families.push_back(std::move(f));
  }

  // perturb = { TABLE.KEY = AXIS, ... }: vehicle parameters by their names
  // in config/phoenix.toml, each an axis within the parameter's range.
  // TOML makes `hull.mass_kg = x` the table hull holding mass_kg; a quoted
  // "hull.mass_kg" is taken too. `where` names the axes for sampling.
  std::vector<Perturbation> read_perturb(const toml::node& node, const std::string& where) {
    std::vector<Perturbation> out;
    const toml::table* t = node.as_table();
    if (t == nullptr || t->empty()) {
      errors_.add(node, fmt::format("'perturb' must be a table of vehicle parameters, e.g. perturb = {{ hull.mass_kg "
                                    "= [170, 180] }} (config/phoenix.toml's names: {})",
                                    vehicle::param_names_text()));
      return out;
    }
    std::vector<std::pair<std::string, const toml::node*>> named;  // "hull.mass_kg", its axis
    bool ok = true;
    for (auto&& [table, inner] : *t) {
      const std::string tname(table.str());
      if (vehicle::find_param(tname) != nullptr) {
        named.emplace_back(tname, &inner);
        continue;
      }
      const toml::table* keys = inner.as_table();
      const bool is_table = keys != nullptr && !keys->contains("from") && !keys->contains("to");
      const bool known = std::any_of(vehicle::param_infos().begin(), vehicle::param_infos().end(),
                                     [&](const vehicle::ParamInfo& p) { return p.name.starts_with(tname + "."); });
      if (!known || !is_table) {
        errors_.add(table, unknown_param_message(tname));
        ok = false;
        continue;
      }
      for (auto&& [key, axis] : *keys) {
        const std::string name = tname + "." + std::string(key.str());
        if (vehicle::find_param(name) == nullptr) {
          errors_.add(key, unknown_param_message(name));
          ok = false;
          continue;
        }
        named.emplace_back(name, &axis);
      }
    }
    for (std::size_t i = 0; i < named.size(); ++i) {
      for (std::size_t k = 0; k < i; ++k) {
        if (named[k].first == named[i].first) {
          errors_.add(*named[i].second, fmt::format("'{}' is perturbed twice in one 'perturb'", named[i].first));
          ok = false;
        }
      }
    }
    if (named.size() > kMaxPerturbedParams) {
      errors_.add(node, fmt::format("'perturb' names {} parameters; at most {} may be perturbed together", named.size(),
                                    kMaxPerturbedParams));
      return {};
    }
    for (const auto& [name, axis] : named) {
      const vehicle::ParamInfo& info = *vehicle::find_param(name);
      if (info.integer && axis->is_table() && axis->as_table()->contains("sampled")) {
        errors_.add(*axis, fmt::format("'{}' is a whole number: give a list or a grid, not 'sampled'", name));
        ok = false;
        continue;
      }
      // A closed lower end is AxisRules' min; an open one is "zero not
      // allowed" there, which it spells for any min.
      AxisRules rules{name, info.lo, info.hi, !info.lo_open, limits_.max_cases};
      auto values = parse_axis(errors_, *axis, rules, spec_.sample_seed, fmt::format("{}.{}", where, name));
      if (!values) {
        ok = false;
        continue;
      }
      for (double v : *values) {
        if (auto why = vehicle::param_value_problem(info, v); !why.empty()) {
          errors_.add(*axis, why);
          ok = false;
          break;
        }
      }
      out.push_back({name, std::move(*values)});
    }
    if (!ok) return {};
    // config/phoenix.toml's order, whatever order the spec wrote them in.
    std::sort(out.begin(), out.end(), [](const Perturbation& a, const Perturbation& b) {
      return vehicle::find_param(a.param) < vehicle::find_param(b.param);
    });
    return out;
  }

  static std::string unknown_param_message(const std::string& name) {
    std::string hint;
    for (const vehicle::ParamInfo& p : vehicle::param_infos()) {
      if (p.name.ends_with("." + name)) hint += fmt::format("{}{}", hint.empty() ? "; did you mean " : " or ", p.name);
    }
    return fmt::format("unknown vehicle parameter '{}'{} (parameters are TABLE.KEY as in config/phoenix.toml: {})",
                       name, hint.empty() ? "" : hint + "?", vehicle::param_names_text());
  }

  // The family's perturbations over the spec's, and every combination of
  // them checked against the rules between parameters (a surface below the
  // tank's bottom is not a vehicle), so no case can fail to build its vehicle.
  void read_family_perturb(const toml::table& t, Family& f) {
    const toml::node* n = t.get("perturb");
    std::vector<Perturbation> own = n ? read_perturb(*n, f.name + ".perturb") : std::vector<Perturbation>{};
    f.perturb = own;
    for (const Perturbation& p : spec_perturb_) {
      if (std::none_of(own.begin(), own.end(), [&](const Perturbation& q) { return q.param == p.param; })) {
        f.perturb.push_back(p);
      }
    }
    std::sort(f.perturb.begin(), f.perturb.end(), [](const Perturbation& a, const Perturbation& b) {
      return vehicle::find_param(a.param) < vehicle::find_param(b.param);
    });
    if (f.perturb.size() > kMaxPerturbedParams) {
      errors_.add(n ? n->source() : t.source(), fmt::format("family '{}' perturbs {} parameters; at most {} together",
                                                            f.name, f.perturb.size(), kMaxPerturbedParams));
      f.perturb.clear();
      return;
    }
    // Only the parameters the rules name can break them: their combinations.
    std::vector<const Perturbation*> related;
    for (const Perturbation& p : f.perturb) {
      if (vehicle::param_in_relations(p.param)) related.push_back(&p);
    }
    std::uint64_t combos = 1;
    for (const Perturbation* p : related) combos = sat_mul(combos, p->values.size());
    if (related.empty() || combos > limits_.max_cases) return;  // too many: the case count says so
    std::vector<std::size_t> at(related.size(), 0);
    for (std::uint64_t i = 0; i < combos; ++i) {
      vehicle::VehicleParams params = vehicle::default_params();
      std::string which;
      for (std::size_t k = 0; k < related.size(); ++k) {
        const double v = related[k]->values[at[k]];
        (void)vehicle::set_param(params, related[k]->param, v);
        which += fmt::format("{}{}={}", which.empty() ? "" : " ", related[k]->param, v);
      }
      if (auto r = vehicle::check_param_relations(params); !r) {
        errors_.add(n ? n->source() : t.source(), fmt::format("family '{}' makes a vehicle that cannot be ({}): {}",
                                                              f.name, which, r.error().message));
        return;
      }
      for (std::size_t k = related.size(); k-- > 0;) {
        if (++at[k] < related[k]->values.size()) break;
        at[k] = 0;
      }
    }
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
