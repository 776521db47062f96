#include "campaign/cases.h"

#include <cassert>
#include <charconv>

#include <fmt/format.h>

namespace strata::campaign {

Case case_at(const Spec& spec, std::uint64_t index) {
  assert(index < spec.case_count());
  Case c;
  c.index = index;
  const std::uint64_t seeds = spec.seeds.size();
  std::uint64_t rest = index;
  for (c.mission = 0; c.mission + 1 < spec.missions.size(); ++c.mission) {
    const std::uint64_t n = spec.combinations_for(c.mission) * seeds;
    if (rest < n) break;
    rest -= n;
  }
  c.seed = spec.seeds[rest % seeds];
  rest /= seeds;  // the fault combination within the mission
  for (std::size_t i = 0; i < spec.families.size(); ++i) {
    const Family& f = spec.families[i];
    if (!f.applies_to(c.mission)) continue;
    if (rest >= f.combinations()) {
      rest -= f.combinations();
      continue;
    }
    c.family = i;
    // Perturbations: the innermost of the family's axes, the last fastest.
    c.params.resize(f.perturb.size());
    for (std::size_t k = f.perturb.size(); k-- > 0;) {
      const std::vector<double>& values = f.perturb[k].values;
      c.params[k] = {f.perturb[k].param, values[rest % values.size()]};
      rest /= values.size();
    }
    if (!f.fault) return c;
    vehicle::Fault fault;
    fault.kind = *f.fault;
    const std::uint64_t nd = f.duration_s.empty() ? 1 : f.duration_s.size();
    const std::uint64_t nh = f.health.empty() ? 1 : f.health.size();
    if (!f.duration_s.empty()) fault.duration_s = f.duration_s[rest % nd];
    rest /= nd;
    if (!f.health.empty()) fault.health = f.health[rest % nh];
    rest /= nh;
    fault.at_s = f.at_s[rest];
    c.fault = fault;
    return c;
  }
  assert(false && "index past the families");
  return c;
}

std::string scenario_toml(const Spec& spec, const Case& c) {
  std::string out = fmt::format("# campaign {} case {}: {}\ndescription = \"{}\"\nseed = {}\n", spec.path, c.index,
                                spec.missions[c.mission].path, fault_text(c), c.seed);
  if (!c.params.empty()) {
    out = fmt::format("# vehicle parameters (with --params, a file of them): {}\n", params_text(c)) + out;
  }
  if (!spec.world_toml.empty()) out += fmt::format("\n# the world of {}\n{}\n", spec.world, spec.world_toml);
  if (c.fault) {
    const vehicle::Fault& f = *c.fault;
    out += fmt::format("\n[[fault]]\nkind = \"{}\"\nat_s = {}\n", vehicle::to_string(f.kind), f.at_s);
    if (f.kind == vehicle::FaultKind::WeakThrusters) out += fmt::format("health = {}\n", f.health);
    if (f.duration_s)
      out += fmt::format("duration_s = {}\n", *f.duration_s);
    else if (f.kind == vehicle::FaultKind::LinkLoss)
      out += "forever = true\n";
  }
  return out;
}

nlohmann::ordered_json case_inputs(const Spec& spec, const Case& c) {
  nlohmann::ordered_json j;
  j["mission"] = spec.missions[c.mission].path;
  j["family"] = spec.families[c.family].name;
  if (!spec.families[c.family].answers.empty()) j["answers"] = spec.families[c.family].answers;
  nlohmann::ordered_json fault;
  if (c.fault) {
    fault["kind"] = vehicle::to_string(c.fault->kind);
    fault["at_s"] = c.fault->at_s;
    if (c.fault->kind == vehicle::FaultKind::WeakThrusters) fault["health"] = c.fault->health;
    if (c.fault->duration_s)
      fault["duration_s"] = *c.fault->duration_s;
    else if (c.fault->kind == vehicle::FaultKind::LinkLoss)
      fault["forever"] = true;
  } else {
    fault["kind"] = "none";
  }
  j["fault"] = std::move(fault);
  if (!c.params.empty()) {
    nlohmann::ordered_json params = nlohmann::ordered_json::object();
    for (const auto& [name, value] : c.params) params[name] = value;
    j["params"] = std::move(params);
  }
  j["seed"] = c.seed;
  return j;
}

std::string fault_text(const Case& c) {
  if (!c.fault) return "none";
  const vehicle::Fault& f = *c.fault;
  std::string s(vehicle::to_string(f.kind));
  if (f.kind == vehicle::FaultKind::WeakThrusters) s += fmt::format(" health {}", f.health);
  s += fmt::format(" at {} s", f.at_s);
  if (f.duration_s)
    s += fmt::format(" for {} s", *f.duration_s);
  else if (f.kind == vehicle::FaultKind::LinkLoss)
    s += " for good";
  return s;
}

std::string params_text(const Case& c) {
  std::string s;
  for (const auto& [name, value] : c.params) s += fmt::format("{}{}={}", s.empty() ? "" : " ", name, value);
  return s;
}

vehicle::VehicleParams case_params(const Spec& spec, const Case& c) {
  vehicle::VehicleParams p = spec.base_params;
  for (const auto& [name, value] : c.params) {
    [[maybe_unused]] const auto set = vehicle::set_param(p, name, value);
    assert(set.ok() && "the spec checked every value");
  }
  return p;
}

namespace {

std::optional<std::uint64_t> parse_index(std::string_view s) {
  std::uint64_t v = 0;
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || s.empty()) return std::nullopt;
  return v;
}

}  // namespace

core::Result<IndexRange> parse_range(const std::string& text, std::uint64_t count) {
  const auto dash = text.find('-');
  const auto first = parse_index(std::string_view(text).substr(0, dash));
  const auto last = dash == std::string::npos ? first : parse_index(std::string_view(text).substr(dash + 1));
  if (!first || !last) {
    return core::make_error(core::ErrorCode::InvalidInput, fmt::format("'{}' is not an index or a range A-B", text));
  }
  if (*first > *last || *last >= count) {
    return core::make_error(core::ErrorCode::InvalidInput,
                            fmt::format("'{}' is outside the campaign's cases 0-{}", text, count - 1));
  }
  return IndexRange{*first, *last};
}

}  // namespace strata::campaign
