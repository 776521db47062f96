#include "vehicle/scenario_world.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <cstdint>
#include <string>

#include <fmt/format.h>

#include "core/toml_reader.h"

namespace strata::vehicle {
namespace {

// A finite number at node with lo <= v <= hi (lo < v when lo_open).
core::Result<double> number_in(std::string_view path, const toml::node& node, std::string_view what, double lo,
                               bool lo_open, double hi) {
  auto v = core::toml_number_at(path, node, what);
  if (!v) return v;
  const double x = v.value();
  const bool lo_ok = lo_open ? x > lo : x >= lo;
  if (!std::isfinite(x) || !lo_ok || x > hi) {
    return core::toml_error_at(path, node.source(),
                               fmt::format("'{}' must be in {}{}, {}]", what, lo_open ? "(" : "[", lo, hi));
  }
  return x;
}

core::Result<const toml::table*> table_with(std::string_view path, const toml::table& root, std::string_view name,
                                            std::initializer_list<std::string_view> keys) {
  const toml::node* node = root.get(name);
  if (node == nullptr) return static_cast<const toml::table*>(nullptr);
  const toml::table* t = node->as_table();
  if (t == nullptr) return core::toml_error_at(path, node->source(), fmt::format("'{}' must be a table", name));
  for (auto&& [key, value] : *t) {
    if (std::find(keys.begin(), keys.end(), key.str()) == keys.end()) {
      return core::toml_error_at(path, key.source(), fmt::format("unknown key '{}' in [{}]", key.str(), name));
    }
  }
  return t;
}

core::Result<std::size_t> count_in(std::string_view path, const toml::table& t, std::string_view key, std::size_t hi) {
  const toml::node* n = t.get(key);
  if (n == nullptr) return core::toml_error_at(path, t.source(), fmt::format("grid seabed without '{}'", key));
  if (!n->is_integer() || *n->value<std::int64_t>() < 2 || *n->value<std::int64_t>() > static_cast<std::int64_t>(hi)) {
    return core::toml_error_at(path, n->source(), fmt::format("'seabed.{}' must be an integer in [2, {}]", key, hi));
  }
  return static_cast<std::size_t>(*n->value<std::int64_t>());
}

core::Result<void> parse_grid(std::string_view path, const toml::table& t, Seabed& bed) {
  auto nx = count_in(path, t, "nx", kMaxGridNodes / 2);
  if (!nx) return nx.error();
  auto ny = count_in(path, t, "ny", kMaxGridNodes / 2);
  if (!ny) return ny.error();
  bed.nx = nx.value();
  bed.ny = ny.value();
  if (bed.nx * bed.ny > kMaxGridNodes) {
    return core::toml_error_at(path, t.source(),
                               fmt::format("grid seabed of {} x {} nodes: at most {}", bed.nx, bed.ny, kMaxGridNodes));
  }
  for (auto [key, out] : {std::pair{"x0_m", &bed.x0_m}, std::pair{"y0_m", &bed.y0_m}}) {
    const toml::node* n = t.get(key);
    if (n == nullptr) return core::toml_error_at(path, t.source(), fmt::format("grid seabed without '{}'", key));
    auto v = number_in(path, *n, fmt::format("seabed.{}", key), -kMaxPlanM, false, kMaxPlanM);
    if (!v) return v.error();
    *out = v.value();
  }
  const toml::node* sp = t.get("spacing_m");
  if (sp == nullptr) return core::toml_error_at(path, t.source(), "grid seabed without 'spacing_m'");
  auto spacing = number_in(path, *sp, "seabed.spacing_m", 0.0, true, kMaxPlanM);
  if (!spacing) return spacing.error();
  bed.spacing_m = spacing.value();

  const toml::node* d = t.get("depths_m");
  if (d == nullptr) return core::toml_error_at(path, t.source(), "grid seabed without 'depths_m'");
  const toml::array* rows = d->as_array();
  if (rows == nullptr || rows->size() != bed.ny) {
    return core::toml_error_at(path, d->source(),
                               fmt::format("'seabed.depths_m' must be an array of ny = {} rows", bed.ny));
  }
  bed.depths_m.clear();
  bed.depths_m.reserve(bed.nx * bed.ny);
  for (std::size_t j = 0; j < rows->size(); ++j) {
    const toml::node& row_node = *rows->get(j);
    const toml::array* row = row_node.as_array();
    if (row == nullptr || row->size() != bed.nx) {
      return core::toml_error_at(path, row_node.source(),
                                 fmt::format("'seabed.depths_m' row {} must hold nx = {} depths", j + 1, bed.nx));
    }
    for (const toml::node& cell : *row) {
      auto v = number_in(path, cell, "seabed.depths_m", 0.0, true, kMaxSeabedDepthM);
      if (!v) return v.error();
      bed.depths_m.push_back(v.value());
    }
  }
  return {};
}

core::Result<void> parse_seabed(std::string_view path, const toml::table& root, Scenario& s) {
  auto found =
      table_with(path, root, "seabed",
                 {"kind", "depth_m", "slope_x", "slope_y", "x0_m", "y0_m", "spacing_m", "nx", "ny", "depths_m"});
  if (!found) return found.error();
  if (found.value() == nullptr) return {};
  const toml::table& t = *found.value();
  if (!s.world.open_water) {
    return core::toml_error_at(path, t.source(), "[seabed] needs open water ([world] kind = \"open_water\")");
  }
  const toml::node* kind = t.get("kind");
  if (kind == nullptr) return core::toml_error_at(path, t.source(), "[seabed] without 'kind'");
  const auto text = kind->value<std::string_view>();
  if (text == "flat") {
    s.seabed.kind = SeabedKind::Flat;
  } else if (text == "slope") {
    s.seabed.kind = SeabedKind::Slope;
  } else if (text == "grid") {
    s.seabed.kind = SeabedKind::Grid;
  } else {
    return core::toml_error_at(path, kind->source(), "'seabed.kind' must be \"flat\", \"slope\" or \"grid\"");
  }
  // Keys that belong to another kind are errors, not silently ignored.
  for (auto&& [key, node] : t) {
    const std::string_view k = key.str();
    const bool ok = k == "kind" || (s.seabed.kind != SeabedKind::Grid && k == "depth_m") ||
                    (s.seabed.kind == SeabedKind::Slope && (k == "slope_x" || k == "slope_y")) ||
                    (s.seabed.kind == SeabedKind::Grid && k != "depth_m" && k != "slope_x" && k != "slope_y");
    if (!ok) {
      return core::toml_error_at(path, key.source(), fmt::format("'{}' is not a key of a {} seabed", k, *text));
    }
  }
  if (s.seabed.kind == SeabedKind::Grid) return parse_grid(path, t, s.seabed);
  const toml::node* depth = t.get("depth_m");
  if (depth == nullptr) return core::toml_error_at(path, t.source(), fmt::format("{} seabed without 'depth_m'", *text));
  auto d = number_in(path, *depth, "seabed.depth_m", 0.0, true, kMaxSeabedDepthM);
  if (!d) return d.error();
  s.seabed.depth_m = d.value();
  for (auto [key, out] : {std::pair{"slope_x", &s.seabed.slope_x}, std::pair{"slope_y", &s.seabed.slope_y}}) {
    if (const toml::node* n = t.get(key)) {
      auto v = number_in(path, *n, fmt::format("seabed.{}", key), -10.0, false, 10.0);
      if (!v) return v.error();
      *out = v.value();
    }
  }
  return {};
}

}  // namespace

core::Result<void> parse_world(std::string_view path, const toml::table& root, Scenario& s) {
  auto found = table_with(path, root, "world", {"kind", "current_x_mps", "current_y_mps"});
  if (!found) return found.error();
  if (const toml::table* t = found.value()) {
    if (const toml::node* kind = t->get("kind")) {
      const auto text = kind->value<std::string_view>();
      if (text != "tank" && text != "open_water") {
        return core::toml_error_at(path, kind->source(), "'world.kind' must be \"tank\" or \"open_water\"");
      }
      s.world.open_water = text == "open_water";
    }
    for (auto [key, out] :
         {std::pair{"current_x_mps", &s.world.current_x_mps}, std::pair{"current_y_mps", &s.world.current_y_mps}}) {
      const toml::node* n = t->get(key);
      if (n == nullptr) continue;
      if (!s.world.open_water) {
        return core::toml_error_at(path, n->source(), "a current needs open water ([world] kind = \"open_water\")");
      }
      auto v = number_in(path, *n, fmt::format("world.{}", key), -kMaxCurrentMps, false, kMaxCurrentMps);
      if (!v) return v.error();
      *out = v.value();
    }
    if (std::hypot(s.world.current_x_mps, s.world.current_y_mps) > kMaxCurrentMps) {
      return core::toml_error_at(path, t->source(), fmt::format("the current must be at most {} m/s", kMaxCurrentMps));
    }
  }
  return parse_seabed(path, root, s);
}

}  // namespace strata::vehicle
