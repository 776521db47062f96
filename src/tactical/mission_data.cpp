#include "tactical/mission_data.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <string_view>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/text.h"
#include "core/toml_reader.h"

namespace strata::tactical {

namespace {

// The [[kind]] tables of root: nullptr (with an error) when the key holds
// something else or an empty list; nullptr alone when it is absent.
const toml::array* table_list(const toml::table& root, std::string_view kind, core::TomlErrors& errors) {
  const toml::node* list = root.get(kind);
  if (!list) return nullptr;
  const toml::array* array = list->as_array();
  if (array && array->empty()) {
    errors.add(*list, fmt::format("the {} list is empty", kind));
    return nullptr;
  }
  if (!array || !array->is_array_of_tables()) {
    errors.add(*list, fmt::format("'{}' must be an array of tables: write each as [[{}]]", kind, kind));
    return nullptr;
  }
  return array;
}

// One table's keys against the known ones (listed in the error as given),
// and its optional name.
void check_entry(const toml::table& t, const std::string& owner, std::initializer_list<std::string_view> known,
                 std::string& name, core::TomlErrors& errors) {
  for (auto&& [key, value] : t) {
    const std::string_view k = key.str();
    if (std::find(known.begin(), known.end(), k) == known.end()) {
      const std::vector<std::string> names(known.begin(), known.end());
      auto s = core::suggest(k, names);
      for (const auto& n : names) {
        if (!s && n.starts_with(std::string(k) + "_")) s = n;  // the unit left off: 'x' for 'x_m'
      }
      errors.add(key, fmt::format("{}: unknown key '{}'{} (known: {}; docs/mission-data.md)", owner, k,
                                  s ? fmt::format(": did you mean '{}'?", *s) : "", fmt::join(known, ", ")));
    }
  }
  if (const toml::node* n = t.get("name")) {
    if (const auto* str = n->as_string()) {
      name = str->get();
    } else {
      errors.add(*n, fmt::format("{}: name must be a string, not {}", owner, core::toml_type_phrase(*n)));
    }
  }
}

std::vector<Setpoint> read_setpoints(const toml::table& root, const DataLimits& limits, core::TomlErrors& errors) {
  std::vector<Setpoint> out;
  for (auto&& [key, node] : root) {
    if (key.str() != "setpoint" && key.str() != "waypoint") {
      errors.add(key, fmt::format("unknown key '{}' at the top level: mission data holds only "
                                  "[[setpoint]] and [[waypoint]] tables",
                                  key.str()));
    }
  }
  const toml::node* list = root.get("setpoint");
  if (!list) {
    if (!root.get("waypoint")) {
      errors.add(toml::source_region{{1, 1}, {1, 1}, nullptr},
                 "no setpoints: add [[setpoint]] tables with depth_m and timeout_s (or [[waypoint]] tables "
                 "with x_m and y_m)");
    }
    return out;
  }
  const toml::array* array = table_list(root, "setpoint", errors);
  if (!array) return out;
  std::size_t index = 0;
  for (const toml::node& node : *array) {
    ++index;
    const toml::table& t = *node.as_table();
    Setpoint sp;
    sp.line = t.source().begin.line;
    const std::string owner = fmt::format("setpoint {}", index);
    check_entry(t, owner, {"depth_m", "name", "timeout_s"}, sp.name, errors);
    if (const toml::node* depth = t.get("depth_m")) {
      auto v = core::toml_number(*depth);
      if (!v) {
        errors.add(*depth, fmt::format("{}: depth_m must be a number of metres, not {}", owner,
                                       core::toml_type_phrase(*depth)));
      } else if (!std::isfinite(*v) || *v < 0 || *v > limits.max_depth_m) {
        errors.add(*depth, fmt::format("{}: depth_m is {} m; it must lie in 0 .. {} m (positive down, "
                                       "within the tank)",
                                       owner, *v, limits.max_depth_m));
      } else {
        sp.depth_m = *v;
      }
    } else {
      errors.add(t, fmt::format("{} has no depth_m", owner));
    }
    if (const toml::node* timeout = t.get("timeout_s")) {
      auto v = core::toml_number(*timeout);
      if (!v) {
        errors.add(*timeout, fmt::format("{}: timeout_s must be a number of seconds, not {}", owner,
                                         core::toml_type_phrase(*timeout)));
      } else if (!std::isfinite(*v) || *v <= 0) {
        errors.add(*timeout, fmt::format("{}: timeout_s is {} s; it must be above 0", owner, *v));
      } else {
        sp.timeout_s = *v;
      }
    } else {
      errors.add(t, fmt::format("{} has no timeout_s", owner));
    }
    out.push_back(std::move(sp));
  }
  return out;
}

std::vector<Waypoint> read_waypoints(const toml::table& root, core::TomlErrors& errors) {
  std::vector<Waypoint> out;
  const toml::array* array = table_list(root, "waypoint", errors);
  if (!array) return out;
  std::size_t index = 0;
  for (const toml::node& node : *array) {
    ++index;
    const toml::table& t = *node.as_table();
    Waypoint wp;
    wp.line = t.source().begin.line;
    const std::string owner = fmt::format("waypoint {}", index);
    check_entry(t, owner, {"name", "x_m", "y_m"}, wp.name, errors);
    for (auto [key, out_v] : {std::pair{"x_m", &wp.x_m}, std::pair{"y_m", &wp.y_m}}) {
      const toml::node* n = t.get(key);
      if (!n) {
        errors.add(t, fmt::format("{} has no {}", owner, key));
        continue;
      }
      auto v = core::toml_number(*n);
      if (!v) {
        errors.add(*n,
                   fmt::format("{}: {} must be a number of metres, not {}", owner, key, core::toml_type_phrase(*n)));
      } else if (!std::isfinite(*v) || std::abs(*v) > kMaxWaypointM) {
        errors.add(*n, fmt::format("{}: {} is {} m; it must lie within +-{} m", owner, key, *v, kMaxWaypointM));
      } else {
        *out_v = *v;
      }
    }
    out.push_back(std::move(wp));
  }
  return out;
}

}  // namespace

core::Result<MissionData> MissionData::parse(std::string_view text, const std::string& source_name,
                                             const DataLimits& limits) {
  auto root = core::parse_toml(text, source_name);
  if (!root) return root.error();
  core::TomlErrors errors(source_name);
  std::vector<Setpoint> setpoints = read_setpoints(root.value(), limits, errors);
  std::vector<Waypoint> waypoints = read_waypoints(root.value(), errors);
  if (!errors.empty()) return errors.error();
  MissionData data;
  data.path_ = source_name;
  data.setpoints_ = std::move(setpoints);
  data.waypoints_ = std::move(waypoints);
  return data;
}

core::Result<MissionData> MissionData::load(const std::string& path, const DataLimits& limits) {
  auto text = core::read_toml_text(path);
  if (!text) return text.error();
  return parse(text.value(), path, limits);
}

core::Result<const Setpoint*> DataCursor::next() {
  ++calls_;
  const auto& all = data_->setpoints();
  if (position_ >= all.size()) {
    return core::make_error(core::ErrorCode::InvalidInput,
                            fmt::format("mission data has {} setpoint{}; next_setpt_data was called "
                                        "a {} time",
                                        all.size(), all.size() == 1 ? "" : "s", ordinal(calls_)));
  }
  return &all[position_++];
}

core::Result<const Waypoint*> DataCursor::next_waypoint() {
  ++waypoint_calls_;
  const auto& all = data_->waypoints();
  if (waypoint_position_ >= all.size()) {
    return core::make_error(core::ErrorCode::InvalidInput,
                            fmt::format("mission data has {} waypoint{}; next_waypoint was called a {} time",
                                        all.size(), all.size() == 1 ? "" : "s", ordinal(waypoint_calls_)));
  }
  return &all[waypoint_position_++];
}

const Waypoint* DataCursor::current_waypoint() const {
  return waypoint_position_ == 0 ? nullptr : &data_->waypoints()[waypoint_position_ - 1];
}

const Setpoint* DataCursor::current() const { return position_ == 0 ? nullptr : &data_->setpoints()[position_ - 1]; }

std::string ordinal(std::size_t n) {
  std::string_view suffix = "th";
  if (n % 100 < 11 || n % 100 > 13) {
    switch (n % 10) {
      case 1: suffix = "st"; break;
      case 2: suffix = "nd"; break;
      case 3: suffix = "rd"; break;
      default: break;
    }
  }
  return fmt::format("{}{}", n, suffix);
}

}  // namespace strata::tactical
