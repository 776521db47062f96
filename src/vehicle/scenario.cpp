#include "vehicle/scenario.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <initializer_list>

#include <fmt/format.h>

#include "vehicle/time_compare.h"
#include "core/toml_reader.h"
#include "vehicle/scenario_table.h"
#include "vehicle/scenario_world.h"

namespace strata::vehicle {

std::string_view to_string(FaultKind kind) {
  switch (kind) {
    case FaultKind::WeakThrusters: return "weak_thrusters";
    case FaultKind::Leak: return "leak";
    case FaultKind::SensorDropout: return "sensor_dropout";
    case FaultKind::LinkLoss: return "link_loss";
    case FaultKind::CompassBias: return "compass_bias";
    case FaultKind::AltimeterDead: return "altimeter_dead";
    case FaultKind::NoGps: return "no_gps";
  }
  return "?";
}

bool Scenario::link_lost(double t_s) const {
  for (const Fault& f : faults) {
    if (f.kind != FaultKind::LinkLoss || !time_reached(t_s, f.at_s)) continue;
    if (!f.duration_s || !time_reached(t_s, f.at_s + *f.duration_s)) return true;
  }
  return false;
}

std::optional<double> Scenario::link_lost_at() const {
  std::optional<double> first;
  for (const Fault& f : faults) {
    if (f.kind == FaultKind::LinkLoss && (!first || f.at_s < *first)) first = f.at_s;
  }
  return first;
}

namespace {

std::optional<FaultKind> kind_from(std::string_view s) {
  for (FaultKind k : {FaultKind::WeakThrusters, FaultKind::Leak, FaultKind::SensorDropout, FaultKind::LinkLoss,
                      FaultKind::CompassBias, FaultKind::AltimeterDead, FaultKind::NoGps}) {
    if (to_string(k) == s) return k;
  }
  return std::nullopt;
}

// Keys a fault of this kind may carry besides kind and at_s.
bool allowed_key(FaultKind kind, std::string_view key) {
  switch (kind) {
    case FaultKind::WeakThrusters: return key == "health";
    case FaultKind::Leak: return false;
    case FaultKind::SensorDropout: return key == "duration_s";
    case FaultKind::LinkLoss: return key == "duration_s" || key == "forever";
    case FaultKind::CompassBias: return key == "bias_deg";
    case FaultKind::AltimeterDead:
    case FaultKind::NoGps: return false;
  }
  return false;
}

core::Result<double> non_negative(std::string_view path, const toml::node& node, std::string_view what,
                                  bool allow_zero) {
  auto v = core::toml_number_at(path, node, what);
  if (!v) return v;
  const double x = v.value();
  if (!std::isfinite(x) || x < 0.0 || (!allow_zero && x == 0.0)) {
    return core::toml_error_at(path, node.source(), fmt::format("'{}' must be {}", what, allow_zero ? ">= 0" : "> 0"));
  }
  return x;
}

core::Result<Fault> parse_fault(std::string_view path, const toml::table& t) {
  const toml::node* kind_node = t.get("kind");
  if (kind_node == nullptr) return core::toml_error_at(path, t.source(), "fault without 'kind'");
  const auto kind_text = kind_node->value<std::string_view>();
  if (!kind_text) return core::toml_error_at(path, kind_node->source(), "'kind' must be a string");
  const auto kind = kind_from(*kind_text);
  if (!kind) {
    return core::toml_error_at(path, kind_node->source(),
                               fmt::format("unknown fault kind '{}' (expected weak_thrusters, leak, "
                                           "sensor_dropout, link_loss, compass_bias, altimeter_dead or no_gps)",
                                           *kind_text));
  }
  Fault f;
  f.kind = *kind;
  for (auto&& [key, node] : t) {
    const std::string_view k = key.str();
    if (k == "kind" || k == "at_s" || allowed_key(*kind, k)) continue;
    return core::toml_error_at(path, key.source(), fmt::format("unknown key '{}' for a {} fault", k, *kind_text));
  }

  const toml::node* at = t.get("at_s");
  if (at == nullptr) return core::toml_error_at(path, t.source(), "fault without 'at_s'");
  auto at_s = non_negative(path, *at, "at_s", true);
  if (!at_s) return at_s.error();
  f.at_s = at_s.value();

  switch (f.kind) {
    case FaultKind::WeakThrusters: {
      const toml::node* h = t.get("health");
      if (h == nullptr) {
        return core::toml_error_at(path, t.source(), "weak_thrusters fault without 'health'");
      }
      auto health = non_negative(path, *h, "health", true);
      if (!health) return health.error();
      if (health.value() > 1.0) {
        return core::toml_error_at(path, h->source(), "'health' must be in [0, 1]");
      }
      f.health = health.value();
      break;
    }
    case FaultKind::Leak:
    case FaultKind::AltimeterDead:
    case FaultKind::NoGps: break;
    case FaultKind::CompassBias: {
      const toml::node* b = t.get("bias_deg");
      if (b == nullptr) return core::toml_error_at(path, t.source(), "compass_bias fault without 'bias_deg'");
      auto bias = core::toml_number_at(path, *b, "bias_deg");
      if (!bias) return bias.error();
      if (!std::isfinite(bias.value()) || std::abs(bias.value()) > 180.0) {
        return core::toml_error_at(path, b->source(), "'bias_deg' must be in [-180, 180]");
      }
      f.bias_deg = bias.value();
      break;
    }
    case FaultKind::SensorDropout:
    case FaultKind::LinkLoss: {
      const toml::node* d = t.get("duration_s");
      const toml::node* forever = t.get("forever");
      if (forever != nullptr) {
        if (!forever->is_boolean() || !*forever->value<bool>()) {
          return core::toml_error_at(path, forever->source(), "'forever' must be true (omit it for a limited loss)");
        }
        if (d != nullptr) {
          return core::toml_error_at(path, d->source(), "give either 'duration_s' or 'forever = true', not both");
        }
        break;
      }
      if (d == nullptr) {
        return core::toml_error_at(path, t.source(),
                                   f.kind == FaultKind::LinkLoss
                                       ? "link_loss fault needs 'duration_s' or 'forever = true'"
                                       : "sensor_dropout fault without 'duration_s'");
      }
      auto dur = non_negative(path, *d, "duration_s", false);
      if (!dur) return dur.error();
      f.duration_s = dur.value();
      break;
    }
  }
  return f;
}

// The table under `name` (nullptr if absent); an error if it is not a table or
// has a key outside `keys`.
core::Result<const toml::table*> optional_table(std::string_view path, const toml::table& root, std::string_view name,
                                                std::initializer_list<std::string_view> keys) {
  const toml::node* node = root.get(name);
  if (node == nullptr) return static_cast<const toml::table*>(nullptr);
  const toml::table* t = node->as_table();
  if (t == nullptr) {
    return core::toml_error_at(path, node->source(), fmt::format("'{}' must be a table", name));
  }
  for (auto&& [key, value] : *t) {
    if (std::find(keys.begin(), keys.end(), key.str()) == keys.end()) {
      return core::toml_error_at(path, key.source(), fmt::format("unknown key '{}' in [{}]", key.str(), name));
    }
  }
  return t;
}

// [vehicle]: every key optional.
core::Result<void> parse_vehicle(std::string_view path, const toml::table& root, Scenario& s) {
  auto t = optional_table(path, root, "vehicle", {"x_m", "y_m", "heading_deg"});
  if (!t) return t.error();
  if (t.value() == nullptr) return {};
  const toml::table& v = *t.value();
  for (auto [key, out] : {std::pair{"x_m", &s.vehicle_x_m}, std::pair{"y_m", &s.vehicle_y_m}}) {
    const toml::node* n = v.get(key);
    if (n == nullptr) continue;
    if (s.world.open_water) {
      auto x = core::toml_number_at(path, *n, fmt::format("vehicle.{}", key));
      if (!x) return x.error();
      if (!std::isfinite(x.value()) || std::abs(x.value()) > kMaxPlanM) {
        return core::toml_error_at(path, n->source(),
                                   fmt::format("'vehicle.{}' must be within +-{} m of the origin", key, kMaxPlanM));
      }
      *out = x.value();
      continue;
    }
    auto x = non_negative(path, *n, fmt::format("vehicle.{}", key), true);
    if (!x) return x.error();
    *out = x.value();
  }
  if (const toml::node* n = v.get("heading_deg")) {
    auto h = non_negative(path, *n, "vehicle.heading_deg", true);
    if (!h) return h.error();
    if (h.value() >= 360.0) {
      return core::toml_error_at(path, n->source(), "'vehicle.heading_deg' must be in [0, 360)");
    }
    s.vehicle_heading_deg = h.value();
  }
  return {};
}

// [target]: every key required.
core::Result<void> parse_target(std::string_view path, const toml::table& root, Scenario& s) {
  auto t = optional_table(path, root, "target", {"x_m", "y_m", "radius_m"});
  if (!t) return t.error();
  if (t.value() == nullptr) return {};
  const toml::table& v = *t.value();
  Target target;
  for (auto [key, out] :
       {std::pair{"x_m", &target.x_m}, std::pair{"y_m", &target.y_m}, std::pair{"radius_m", &target.radius_m}}) {
    const toml::node* n = v.get(key);
    if (n == nullptr) {
      return core::toml_error_at(path, v.source(), fmt::format("target without '{}'", key));
    }
    const bool radius = std::string_view(key) == "radius_m";
    auto x = non_negative(path, *n, fmt::format("target.{}", key), !radius);
    if (!x) return x.error();
    *out = x.value();
  }
  s.target = target;
  return {};
}

}  // namespace

core::Result<Scenario> scenario_from_table(std::string_view path, const toml::table& root) {
  Scenario s;
  for (auto&& [key, node] : root) {
    const std::string_view k = key.str();
    if (k != "seed" && k != "description" && k != "fault" && k != "vehicle" && k != "target" && k != "world" &&
        k != "seabed") {
      return core::toml_error_at(path, key.source(), fmt::format("unknown key '{}'", k));
    }
  }
  const toml::node* seed = root.get("seed");
  if (seed == nullptr) return core::toml_error_in(path, "missing 'seed'");
  if (!seed->is_integer() || *seed->value<std::int64_t>() < 0) {
    return core::toml_error_at(path, seed->source(), "'seed' must be an integer >= 0");
  }
  s.seed = static_cast<std::uint64_t>(*seed->value<std::int64_t>());

  if (const toml::node* d = root.get("description")) {
    if (!d->is_string()) {
      return core::toml_error_at(path, d->source(), "'description' must be a string");
    }
    s.description = *d->value<std::string>();
  }

  if (const toml::node* faults = root.get("fault")) {
    const toml::array* arr = faults->as_array();
    if (arr == nullptr || (!arr->empty() && !arr->is_array_of_tables())) {
      return core::toml_error_at(path, faults->source(), "'fault' must be an array of tables ([[fault]])");
    }
    for (const toml::node& n : *arr) {
      auto f = parse_fault(path, *n.as_table());
      if (!f) return f.error();
      s.faults.push_back(f.value());
    }
  }
  if (auto r = parse_world(path, root, s); !r) return r.error();
  if (auto r = parse_vehicle(path, root, s); !r) return r.error();
  if (auto r = parse_target(path, root, s); !r) return r.error();
  return s;
}

core::Result<Scenario> load_scenario(std::string_view path) {
  auto table = core::parse_toml_file(std::string(path));
  if (!table) return table.error();
  return scenario_from_table(path, table.value());
}

core::Result<Scenario> parse_scenario(std::string_view text, std::string_view path) {
  auto table = core::parse_toml(text, path);
  if (!table) return table.error();
  return scenario_from_table(path, table.value());
}

}  // namespace strata::vehicle
