#include "campaign/spec_perturb.h"

#include <algorithm>

#include <fmt/format.h>

#include "campaign/axis.h"
#include "vehicle/params.h"

namespace strata::campaign {
namespace {

std::string unknown_param_message(const std::string& name) {
  std::string hint;
  for (const vehicle::ParamInfo& p : vehicle::param_infos()) {
    if (p.name.ends_with("." + name)) hint += fmt::format("{}{}", hint.empty() ? "; did you mean " : " or ", p.name);
  }
  return fmt::format("unknown vehicle parameter '{}'{} (parameters are TABLE.KEY as in config/phoenix.toml: {})", name,
                     hint.empty() ? "" : hint + "?", vehicle::param_names_text());
}

}  // namespace

// perturb = { TABLE.KEY = AXIS, ... }: vehicle parameters by their names
// in config/phoenix.toml, each an axis within the parameter's range.
// TOML makes `hull.mass_kg = x` the table hull holding mass_kg; a quoted
// "hull.mass_kg" is taken too. `where` names the axes for sampling.
std::vector<Perturbation> read_perturb(core::TomlErrors& errors, const toml::node& node, const std::string& where,
                                       std::uint64_t sample_seed, std::uint64_t max_cases) {
  std::vector<Perturbation> out;
  const toml::table* t = node.as_table();
  if (t == nullptr || t->empty()) {
    errors.add(node, fmt::format("'perturb' must be a table of vehicle parameters, e.g. perturb = {{ hull.mass_kg "
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
      errors.add(table, unknown_param_message(tname));
      ok = false;
      continue;
    }
    for (auto&& [key, axis] : *keys) {
      const std::string name = tname + "." + std::string(key.str());
      if (vehicle::find_param(name) == nullptr) {
        errors.add(key, unknown_param_message(name));
        ok = false;
        continue;
      }
      named.emplace_back(name, &axis);
    }
  }
  for (std::size_t i = 0; i < named.size(); ++i) {
    for (std::size_t k = 0; k < i; ++k) {
      if (named[k].first == named[i].first) {
        errors.add(*named[i].second, fmt::format("'{}' is perturbed twice in one 'perturb'", named[i].first));
        ok = false;
      }
    }
  }
  if (named.size() > kMaxPerturbedParams) {
    errors.add(node, fmt::format("'perturb' names {} parameters; at most {} may be perturbed together", named.size(),
                                 kMaxPerturbedParams));
    return {};
  }
  for (const auto& [name, axis] : named) {
    const vehicle::ParamInfo& info = *vehicle::find_param(name);
    if (info.integer && axis->is_table() && axis->as_table()->contains("sampled")) {
      errors.add(*axis, fmt::format("'{}' is a whole number: give a list or a grid, not 'sampled'", name));
      ok = false;
      continue;
    }
    // A closed lower end is AxisRules' min; an open one is "zero not
    // allowed" there, which it spells for any min.
    AxisRules rules{name, info.lo, info.hi, !info.lo_open, max_cases};
    auto values = parse_axis(errors, *axis, rules, sample_seed, fmt::format("{}.{}", where, name));
    if (!values) {
      ok = false;
      continue;
    }
    for (double v : *values) {
      if (auto why = vehicle::param_value_problem(info, v); !why.empty()) {
        errors.add(*axis, why);
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

// The family's perturbations over the spec's, and every combination of
// them checked against the rules between parameters (a surface below the
// tank's bottom is not a vehicle), so no case can fail to build its vehicle.
void read_family_perturb(core::TomlErrors& errors, const toml::table& t, Family& f,
                         const std::vector<Perturbation>& spec_perturb, const vehicle::VehicleParams& base,
                         std::uint64_t sample_seed, std::uint64_t max_cases) {
  const toml::node* n = t.get("perturb");
  std::vector<Perturbation> own =
      n ? read_perturb(errors, *n, f.name + ".perturb", sample_seed, max_cases) : std::vector<Perturbation>{};
  f.perturb = own;
  for (const Perturbation& p : spec_perturb) {
    if (std::none_of(own.begin(), own.end(), [&](const Perturbation& q) { return q.param == p.param; })) {
      f.perturb.push_back(p);
    }
  }
  std::sort(f.perturb.begin(), f.perturb.end(), [](const Perturbation& a, const Perturbation& b) {
    return vehicle::find_param(a.param) < vehicle::find_param(b.param);
  });
  if (f.perturb.size() > kMaxPerturbedParams) {
    errors.add(n ? n->source() : t.source(), fmt::format("family '{}' perturbs {} parameters; at most {} together",
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
  if (related.empty() || combos > max_cases) return;  // too many: the case count says so
  std::vector<std::size_t> at(related.size(), 0);
  for (std::uint64_t i = 0; i < combos; ++i) {
    vehicle::VehicleParams params = base;
    std::string which;
    for (std::size_t k = 0; k < related.size(); ++k) {
      const double v = related[k]->values[at[k]];
      (void)vehicle::set_param(params, related[k]->param, v);
      which += fmt::format("{}{}={}", which.empty() ? "" : " ", related[k]->param, v);
    }
    if (auto r = vehicle::check_param_relations(params); !r) {
      errors.add(n ? n->source() : t.source(),
                 fmt::format("family '{}' makes a vehicle that cannot be ({}): {}", f.name, which, r.error().message));
      return;
    }
    for (std::size_t k = related.size(); k-- > 0;) {
      if (++at[k] < related[k]->values.size()) break;
      at[k] = 0;
    }
  }
}

}  // namespace strata::campaign
