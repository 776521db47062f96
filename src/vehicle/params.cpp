#include "vehicle/params.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <variant>

#include <fmt/format.h>

#include "core/toml_reader.h"

namespace strata::vehicle {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// One entry per parameter: where it lives in the file, where it goes in the
// struct, and its admissible range (lo < v or lo <= v; v <= hi).
struct Field {
  std::string_view table;
  std::string_view key;
  std::variant<double VehicleParams::*, int VehicleParams::*> member;
  double lo;
  bool lo_open;
  double hi;
};

const Field kFields[] = {
    {"hull", "mass_kg", &VehicleParams::mass_kg, 0.0, true, kInf},
    {"hull", "added_mass_kg", &VehicleParams::added_mass_kg, 0.0, false, kInf},
    {"hull", "drag_coeff", &VehicleParams::drag_coeff, 0.0, false, kInf},
    {"hull", "buoyancy_n", &VehicleParams::buoyancy_n, -kInf, true, kInf},
    {"thrusters", "max_n", &VehicleParams::thruster_max_n, 0.0, false, kInf},
    {"thrusters", "lag_s", &VehicleParams::thruster_lag_s, 0.0, false, kInf},
    {"depth_cell", "noise_m", &VehicleParams::depth_noise_m, 0.0, false, kInf},
    {"filter", "alpha", &VehicleParams::filter_alpha, 0.0, true, 1.0},
    {"filter", "beta", &VehicleParams::filter_beta, 0.0, true, 2.0},
    {"controller", "lambda_per_s", &VehicleParams::ctrl_lambda_per_s, 0.0, true, kInf},
    {"controller", "gain_n", &VehicleParams::ctrl_gain_n, 0.0, false, kInf},
    {"controller", "boundary_mps", &VehicleParams::ctrl_phi_mps, 0.0, true, kInf},
    {"yaw", "inertia_kgm2", &VehicleParams::yaw_inertia_kgm2, 0.0, true, kInf},
    {"yaw", "added_inertia_kgm2", &VehicleParams::yaw_added_inertia_kgm2, 0.0, false, kInf},
    {"yaw", "drag_coeff", &VehicleParams::yaw_drag_coeff, 0.0, false, kInf},
    {"yaw", "thruster_max_n", &VehicleParams::transverse_max_n, 0.0, false, kInf},
    {"yaw", "lever_arm_m", &VehicleParams::transverse_lever_m, 0.0, false, kInf},
    {"yaw", "lag_s", &VehicleParams::transverse_lag_s, 0.0, false, kInf},
    {"heading_controller", "lambda_per_s", &VehicleParams::hdg_lambda_per_s, 0.0, true, kInf},
    {"heading_controller", "max_rate_dps", &VehicleParams::hdg_max_rate_dps, 0.0, true, kInf},
    {"heading_controller", "gain_nm", &VehicleParams::hdg_gain_nm, 0.0, false, kInf},
    {"heading_controller", "boundary_dps", &VehicleParams::hdg_phi_dps, 0.0, true, kInf},
    {"simulation", "cycle_s", &VehicleParams::cycle_s, 0.0, true, 60.0},
    {"simulation", "substeps", &VehicleParams::substeps, 1.0, false, 10000.0},
    {"simulation", "tank_depth_m", &VehicleParams::tank_depth_m, 0.0, true, kInf},
    {"tank", "length_x_m", &VehicleParams::tank_length_x_m, 0.0, true, kInf},
    {"tank", "width_y_m", &VehicleParams::tank_width_y_m, 0.0, true, kInf},
    {"surge", "added_mass_kg", &VehicleParams::surge_added_mass_kg, 0.0, false, kInf},
    {"surge", "drag_coeff", &VehicleParams::surge_drag_coeff, 0.0, true, kInf},
    {"surge", "motor_max_n", &VehicleParams::motor_max_n, 0.0, false, kInf},
    {"surge", "lag_s", &VehicleParams::motor_lag_s, 0.0, false, kInf},
    {"sway", "added_mass_kg", &VehicleParams::sway_added_mass_kg, 0.0, false, kInf},
    {"sway", "drag_coeff", &VehicleParams::sway_drag_coeff, 0.0, true, kInf},
    {"navigation", "gps_noise_m", &VehicleParams::gps_noise_m, 0.0, true, kInf},
    {"navigation", "gps_period_s", &VehicleParams::gps_period_s, 0.0, true, 3600.0},
    {"navigation", "gps_max_depth_m", &VehicleParams::gps_max_depth_m, 0.0, false, kInf},
    {"navigation", "initial_sd_m", &VehicleParams::nav_initial_sd_m, 0.0, true, kInf},
    {"navigation", "speed_sd_mps", &VehicleParams::nav_speed_sd_mps, 0.0, false, kInf},
    {"navigation", "current_sd_mps", &VehicleParams::nav_current_sd_mps, 0.0, true, kInf},
    {"navigation", "current_walk_mps", &VehicleParams::nav_current_walk_mps, 0.0, false, kInf},
    {"navigation", "position_limit_m", &VehicleParams::position_limit_m, 0.0, true, kInf},
    {"guidance", "lookahead_m", &VehicleParams::los_lookahead_m, 0.0, true, kInf},
    {"guidance", "waypoint_radius_m", &VehicleParams::waypoint_radius_m, 0.0, true, kInf},
    {"guidance", "cruise_speed_mps", &VehicleParams::cruise_speed_mps, 0.0, true, kInf},
    {"guidance", "max_depth_m", &VehicleParams::max_depth_m, 0.0, true, 11000.0},
    {"altimeter", "range_m", &VehicleParams::altimeter_range_m, 0.0, true, kInf},
    {"altimeter", "noise_m", &VehicleParams::altimeter_noise_m, 0.0, false, kInf},
    {"altimeter", "floor_m", &VehicleParams::altitude_floor_m, 0.0, false, kInf},
    {"sonar", "beam_width_deg", &VehicleParams::sonar_beam_width_deg, 0.0, true, 90.0},
    {"sonar", "step_deg", &VehicleParams::sonar_step_deg, 0.0, true, 90.0},
    {"sonar", "sector_half_deg", &VehicleParams::sonar_sector_half_deg, 0.0, false, 180.0},
    {"sonar", "ping_period_s", &VehicleParams::sonar_ping_period_s, 0.0, true, 60.0},
    {"sonar", "range_m", &VehicleParams::sonar_range_m, 0.0, true, kInf},
    {"sonar", "bins", &VehicleParams::sonar_bins, 1.0, false, 4096.0},
    {"sonar", "noise", &VehicleParams::sonar_noise, 0.0, false, 255.0},
    {"sonar", "wall_echo", &VehicleParams::sonar_wall_echo, 0.0, false, 255.0},
    {"sonar", "target_echo", &VehicleParams::sonar_target_echo, 0.0, false, 255.0},
    {"sonar", "buffer_pings", &VehicleParams::sonar_buffer_pings, 1.0, false, 1e6},
    {"sonar", "detect_threshold", &VehicleParams::sonar_detect_threshold, 0.0, true, 255.0},
    {"sonar", "detect_margin_m", &VehicleParams::sonar_detect_margin_m, 0.0, false, kInf},
    {"sonar", "detect_min_pings", &VehicleParams::sonar_detect_min_pings, 1.0, false, 1e6},
    {"detection", "depth_tolerance_m", &VehicleParams::depth_tolerance_m, 0.0, true, kInf},
    {"detection", "settle_rate_mps", &VehicleParams::settle_rate_mps, 0.0, true, kInf},
    {"detection", "surface_depth_m", &VehicleParams::surface_depth_m, 0.0, false, kInf},
    {"detection", "heading_tolerance_deg", &VehicleParams::heading_tolerance_deg, 0.0, true, 180.0},
    {"detection", "heading_settle_dps", &VehicleParams::heading_settle_dps, 0.0, true, kInf},
    {"watchdog", "silence_s", &VehicleParams::watchdog_s, 0.0, true, kInf},
};

const Field* find_field(std::string_view table, std::string_view key) {
  for (const Field& f : kFields) {
    if (f.table == table && f.key == key) return &f;
  }
  return nullptr;
}

const Field* find_field(std::string_view name) {
  const auto dot = name.find('.');
  if (dot == std::string_view::npos) return nullptr;
  return find_field(name.substr(0, dot), name.substr(dot + 1));
}

bool known_table(std::string_view table) {
  for (const Field& f : kFields) {
    if (f.table == table) return true;
  }
  return false;
}

bool is_integer(const Field& f) { return std::holds_alternative<int VehicleParams::*>(f.member); }

ParamInfo info_of(const Field& f) {
  return ParamInfo{fmt::format("{}.{}", f.table, f.key), f.lo, f.lo_open, f.hi, is_integer(f)};
}

std::string range_text(const Field& f) { return param_range_text(info_of(f)); }

void assign(const Field& f, VehicleParams& p, double v) {
  if (auto* m = std::get_if<int VehicleParams::*>(&f.member)) {
    p.** m = static_cast<int>(v);
  } else {
    p.*std::get<double VehicleParams::*>(f.member) = v;
  }
}

core::Result<void> set_field(std::string_view path, const Field& f, const toml::node& node, VehicleParams& p) {
  const std::string name = fmt::format("{}.{}", f.table, f.key);
  double v = 0.0;
  if (is_integer(f)) {
    if (!node.is_integer()) {
      return core::toml_error_at(path, node.source(), fmt::format("'{}' must be an integer", name));
    }
    v = static_cast<double>(*node.value<std::int64_t>());
  } else {
    auto n = core::toml_number_at(path, node, name);
    if (!n) return n.error();
    v = n.value();
  }
  const bool lo_ok = f.lo_open ? v > f.lo : v >= f.lo;
  if (!std::isfinite(v) || !lo_ok || v > f.hi) {
    return core::toml_error_at(path, node.source(),
                               fmt::format("'{}' = {} is out of range ({})", name, v, range_text(f)));
  }
  assign(f, p, v);
  return {};
}

core::Result<VehicleParams> params_from_table(std::string_view path, const toml::table& root) {
  VehicleParams p;
  for (auto&& [tname, tnode] : root) {
    if (!known_table(tname.str())) {
      return core::toml_error_at(path, tname.source(), fmt::format("unknown table '{}'", tname.str()));
    }
    const toml::table* t = tnode.as_table();
    if (t == nullptr) {
      return core::toml_error_at(path, tnode.source(), fmt::format("'{}' must be a table", tname.str()));
    }
    for (auto&& [key, node] : *t) {
      const Field* f = find_field(tname.str(), key.str());
      if (f == nullptr) {
        return core::toml_error_at(path, key.source(), fmt::format("unknown key '{}.{}'", tname.str(), key.str()));
      }
      if (auto r = set_field(path, *f, node, p); !r) return r.error();
    }
  }
  for (const Field& f : kFields) {
    const toml::node* node = root.at_path(fmt::format("{}.{}", f.table, f.key)).node();
    if (node == nullptr) {
      return core::toml_error_in(path, fmt::format("missing key '{}.{}'", f.table, f.key));
    }
  }
  if (auto r = check_param_relations(p); !r) return core::toml_error_in(path, r.error().message);
  return p;
}

}  // namespace

core::Result<VehicleParams> load_params(std::string_view path) {
  auto table = core::parse_toml_file(std::string(path));
  if (!table) return table.error();
  return params_from_table(path, table.value());
}

core::Result<VehicleParams> parse_params(std::string_view text, std::string_view path) {
  auto table = core::parse_toml(text, path);
  if (!table) return table.error();
  return params_from_table(path, table.value());
}

}  // namespace strata::vehicle

namespace strata::vehicle {

const std::vector<ParamInfo>& param_infos() {
  static const std::vector<ParamInfo> infos = [] {
    std::vector<ParamInfo> v;
    for (const Field& f : kFields) v.push_back(info_of(f));
    return v;
  }();
  return infos;
}

const ParamInfo* find_param(std::string_view name) {
  for (const ParamInfo& info : param_infos()) {
    if (info.name == name) return &info;
  }
  return nullptr;
}

std::string param_range_text(const ParamInfo& f) {
  if (f.lo == -kInf && f.hi == kInf) return "any finite value";
  std::string lo = f.lo == -kInf ? "" : fmt::format("{} {} ", f.lo, f.lo_open ? "<" : "<=");
  std::string hi = f.hi == kInf ? "" : fmt::format(" <= {}", f.hi);
  return lo + "value" + hi + (f.integer ? ", a whole number" : "");
}

std::string param_value_problem(const ParamInfo& f, double v) {
  const bool lo_ok = f.lo_open ? v > f.lo : v >= f.lo;
  if (!std::isfinite(v) || !lo_ok || v > f.hi) {
    return fmt::format("'{}' = {} is out of range ({})", f.name, v, param_range_text(f));
  }
  if (f.integer && v != std::floor(v)) return fmt::format("'{}' = {} is not a whole number", f.name, v);
  return {};
}

std::string param_names_text() {
  std::string out;
  std::string_view table;
  for (const Field& f : kFields) {
    if (f.table != table) {
      out += fmt::format("{}{}: {}", table.empty() ? "" : "; ", f.table, f.key);
      table = f.table;
    } else {
      out += fmt::format(", {}", f.key);
    }
  }
  return out;
}

core::Result<void> set_param(VehicleParams& p, std::string_view name, double value) {
  const Field* f = find_field(name);
  if (f == nullptr) {
    return core::make_error(core::ErrorCode::InvalidInput, fmt::format("unknown vehicle parameter '{}'", name));
  }
  if (auto why = param_value_problem(info_of(*f), value); !why.empty()) {
    return core::make_error(core::ErrorCode::InvalidInput, why);
  }
  assign(*f, p, value);
  return {};
}

core::Result<void> check_param_relations(const VehicleParams& p) {
  if (p.surface_depth_m >= p.tank_depth_m) {
    return core::make_error(core::ErrorCode::InvalidInput,
                            "detection.surface_depth_m must be less than simulation.tank_depth_m");
  }
  if (p.cruise_speed_mps > p.top_speed_mps()) {
    return core::make_error(core::ErrorCode::InvalidInput,
                            fmt::format("guidance.cruise_speed_mps must not exceed the top speed, {:.3g} m/s "
                                        "(surge.motor_max_n and surge.drag_coeff)",
                                        p.top_speed_mps()));
  }
  return {};
}

bool param_in_relations(std::string_view name) {
  return name == "detection.surface_depth_m" || name == "simulation.tank_depth_m" ||
         name == "guidance.cruise_speed_mps" || name == "surge.motor_max_n" || name == "surge.drag_coeff";
}

std::string params_toml(const VehicleParams& p) {
  std::string out = "# The simulated vehicle's parameters (config/phoenix.toml's keys).\n";
  std::string_view table;
  for (const Field& f : kFields) {
    if (f.table != table) {
      out += fmt::format("\n[{}]\n", f.table);
      table = f.table;
    }
    if (const auto* m = std::get_if<int VehicleParams::*>(&f.member)) {
      out += fmt::format("{} = {}\n", f.key, p.**m);
    } else {
      // The shortest text that reads back as the same double.
      const double v = p.*std::get<double VehicleParams::*>(f.member);
      out += fmt::format("{} = {}\n", f.key, v);
    }
  }
  return out;
}

}  // namespace strata::vehicle
