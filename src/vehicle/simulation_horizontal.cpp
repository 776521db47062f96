// The Simulation's horizontal plane: surge, guidance, dead reckoning, GPS
// and the altimeter's floor (simulation.h states the decisions).
#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "core/units.h"
#include "vehicle/simulation.h"
#include "vehicle/time_compare.h"

namespace strata::vehicle {
namespace {

// (simulation.cpp has its own `refused`: a distinct name keeps the unity build whole.)
core::Error refused_here(std::string message) {
  return core::make_error(core::ErrorCode::InvalidInput, std::move(message));
}

}  // namespace

double Simulation::compass_deg() const { return wrap_heading_deg(yaw_.heading_deg + faults_.compass_bias_deg); }

double Simulation::bottom_m() const {
  return open_water() ? scenario_.seabed.depth_at(x_m_, y_m_) : params_.tank_depth_m;
}

core::Result<void> Simulation::set_speed(double speed_mps) {
  if (auto r = require_network(); !r) return r;
  const double top = params_.top_speed_mps();
  if (!std::isfinite(speed_mps) || speed_mps < 0.0 || speed_mps > top) {
    return refused_here(fmt::format("speed {} m/s outside 0 to {:.3g} m/s (the top speed)", speed_mps, top));
  }
  if (watchdog_tripped_) return refused_here("watchdog tripped: surfacing until the network restarts");
  speed_target_mps_ = speed_mps;
  return {};
}

core::Result<void> Simulation::set_sway(double speed_mps) {
  if (auto r = require_network(); !r) return r;
  const double top = params_.top_sway_speed_mps();
  if (!std::isfinite(speed_mps) || std::abs(speed_mps) > top) {
    return refused_here(
        fmt::format("sway speed {} m/s outside -{:.3g} to {:.3g} m/s (the top sway speed)", speed_mps, top, top));
  }
  if (watchdog_tripped_) return refused_here("watchdog tripped: surfacing until the network restarts");
  sway_target_mps_ = speed_mps;
  return {};
}

core::Result<void> Simulation::check_goal(double x_m, double y_m) const {
  if (!std::isfinite(x_m) || !std::isfinite(y_m)) return refused_here("waypoint coordinates must be finite numbers");
  if (!open_water()) {
    if (x_m < 0.0 || x_m > params_.tank_length_x_m || y_m < 0.0 || y_m > params_.tank_width_y_m) {
      return refused_here(fmt::format("waypoint ({}, {}) m is outside the {} x {} m tank", x_m, y_m,
                                      params_.tank_length_x_m, params_.tank_width_y_m));
    }
    return {};
  }
  const double d = std::hypot(x_m - nav_.x_m(), y_m - nav_.y_m());
  if (!(d <= kMaxLegM)) {
    return refused_here(fmt::format("waypoint ({}, {}) m is {:.0f} m away: farther than the longest leg, {:.0f} m", x_m,
                                    y_m, d, kMaxLegM));
  }
  return {};
}

core::Result<void> Simulation::engage(Guidance g) {
  if (auto r = require_network(); !r) return r;
  if (watchdog_tripped_) return refused_here("watchdog tripped: surfacing until the network restarts");
  guidance_ = g;
  reached_ = false;
  if (!speed_target_mps_ || *speed_target_mps_ == 0.0) speed_target_mps_ = params_.cruise_speed_mps;
  guide();  // the heading target now, so heading_reached is meaningful at once
  return {};
}

core::Result<void> Simulation::goto_xy(double x_m, double y_m) {
  if (auto r = check_goal(x_m, y_m); !r) return r;
  return engage({GuidanceMode::Waypoint, 0.0, 0.0, x_m, y_m});
}

core::Result<void> Simulation::track(double x0_m, double y0_m, double x1_m, double y1_m) {
  if (auto r = check_goal(x0_m, y0_m); !r) return r;
  if (auto r = check_goal(x1_m, y1_m); !r) return r;
  if (std::hypot(x1_m - x0_m, y1_m - y0_m) < params_.waypoint_radius_m) {
    return refused_here(fmt::format("track line shorter than the waypoint radius, {} m", params_.waypoint_radius_m));
  }
  return engage({GuidanceMode::Track, x0_m, y0_m, x1_m, y1_m});
}

core::Result<void> Simulation::stop() {
  if (auto r = require_network(); !r) return r;
  speed_target_mps_ = 0.0;
  sway_target_mps_.reset();
  guidance_ = {};
  reached_ = false;
  return {};
}

core::Result<void> Simulation::goto_depth(double depth_m) {
  if (auto r = require_network(); !r) return r;
  if (watchdog_tripped_) return refused_here("watchdog tripped: surfacing until the network restarts");
  const auto keep = loaded_;
  if (auto r = set_setpoint(depth_m, 1e9); !r) return r;
  if (auto r = start_depth_filter(); !r) return r;
  if (auto r = submerge(); !r) {
    loaded_ = keep;
    return r;
  }
  return {};
}

core::Result<void> Simulation::gps_fix() {
  if (auto r = require_network(); !r) return r;
  if (!open_water()) return refused_here("no GPS in the tank");
  if (faults_.no_gps) return refused_here("no GPS fix (the receiver hears no satellites)");
  if (heave_.depth_m > params_.gps_max_depth_m) {
    return refused_here(fmt::format("no GPS fix at {:.2f} m depth: the antenna is under water", heave_.depth_m));
  }
  nav_.fix(gps_x_noise_.sample(x_m_, false).value_or(x_m_), gps_y_noise_.sample(y_m_, false).value_or(y_m_),
           params_.gps_noise_m);
  next_gps_s_ = time_s() + params_.gps_period_s;
  return {};
}

core::Result<void> Simulation::set_altitude_floor(double floor_m) {
  if (auto r = require_network(); !r) return r;
  if (!std::isfinite(floor_m) || floor_m < 0.0 || floor_m > params_.altimeter_range_m) {
    return refused_here(fmt::format("altitude floor {} m outside 0 to {} m (the altimeter's range)", floor_m,
                                    params_.altimeter_range_m));
  }
  altitude_floor_m_ = floor_m;
  return {};
}

bool Simulation::altitude_low() const {
  if (faults_.altimeter_dead) return heave_.depth_m > params_.surface_depth_m;
  return altitude_m_ && *altitude_m_ < altitude_floor_m_;
}

// Guidance sets the heading law's target once a cycle, from the estimate.
void Simulation::guide() {
  if (guidance_.mode == GuidanceMode::None) return;
  if (!reached_ && guidance_reached(params_, guidance_, nav_.x_m(), nav_.y_m())) {
    reached_ = true;
    event(fmt::format("guidance: {} reached at ({:.1f}, {:.1f}) m (estimated)", to_string(guidance_.mode), nav_.x_m(),
                      nav_.y_m()));
  }
  if (reached_) return;  // run on along the last heading
  GuidanceInput in{nav_.x_m(), nav_.y_m(), nav_.current_x_mps(), nav_.current_y_mps(),
                   speed_target_mps_.value_or(params_.cruise_speed_mps)};
  heading_target_deg_ = guidance_heading_deg(params_, guidance_, in);
}

// One sub-step of surge and of the true position: water velocity along the
// true heading plus the current; the tank's walls hold the vehicle in.
void Simulation::move_substep(double h_s) {
  const double thrust = speed_target_mps_ ? speed_thrust_n(params_, *speed_target_mps_) : 0.0;
  advance_surge(params_, thrust, params_.max_surge_thrust_n() * faults_.thrust_health, h_s, surge_);
  const double psi = yaw_.heading_deg * core::kRadPerDeg;
  x_m_ += h_s * (surge_.speed_mps * std::sin(psi) + scenario_.world.current_x_mps);
  y_m_ += h_s * (surge_.speed_mps * std::cos(psi) + scenario_.world.current_y_mps);
  // Sway, to starboard (heading + 90 degrees). Skipped while at rest, so a
  // vehicle never asked to sway moves exactly as before sway existed.
  advance_sway(params_, sway_force_cmd_n_, params_.max_sway_force_n(), h_s, sway_);
  advance_sway(params_, sway_model_cmd_n_, params_.max_sway_force_n(), h_s, sway_model_);
  if (sway_.speed_mps != 0.0) {
    x_m_ += h_s * sway_.speed_mps * std::cos(psi);
    y_m_ -= h_s * sway_.speed_mps * std::sin(psi);
  }
  if (!open_water()) {
    x_m_ = std::clamp(x_m_, 0.0, params_.tank_length_x_m);
    y_m_ = std::clamp(y_m_, 0.0, params_.tank_width_y_m);
  }
}

// Dead reckoning over the cycle just run, then a GPS fix if one is due.
void Simulation::navigate() {
  if (!open_water()) {
    nav_ = Navigator(params_, x_m_, y_m_, 0.0);  // the tank's positioning: the truth
    return;
  }
  const double psi = compass_deg() * core::kRadPerDeg;
  if (sway_model_.speed_mps == 0.0) {
    nav_.predict(surge_.speed_mps * std::sin(psi), surge_.speed_mps * std::cos(psi), params_.cycle_s);
  } else {  // the modelled sway, to starboard, on top of the measured surge
    const double v = sway_model_.speed_mps;
    nav_.predict(surge_.speed_mps * std::sin(psi) + v * std::cos(psi),
                 surge_.speed_mps * std::cos(psi) - v * std::sin(psi), params_.cycle_s);
  }
  if (faults_.no_gps || heave_.depth_m > params_.gps_max_depth_m) return;
  if (!time_reached(time_s(), next_gps_s_)) return;
  nav_.fix(gps_x_noise_.sample(x_m_, false).value_or(x_m_), gps_y_noise_.sample(y_m_, false).value_or(y_m_),
           params_.gps_noise_m);
  next_gps_s_ = time_s() + params_.gps_period_s;
}

}  // namespace strata::vehicle
