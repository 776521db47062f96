// The Simulation's horizontal plane: surge, guidance, dead reckoning, GPS
// and the altimeter's floor (simulation.h states the decisions).
#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "core/units.h"
#include "vehicle/drag_axis.h"
#include "vehicle/simulation.h"
#include "vehicle/time_compare.h"

namespace strata::vehicle {
namespace {

// (simulation.cpp has its own `refused`: a distinct name keeps the unity build whole.)
core::Error refused_here(std::string message) {
  return core::make_error(core::ErrorCode::InvalidInput, std::move(message));
}

// The hold law's gain and its astern limit (estimates, like
// config/phoenix.toml's; simulation.h).
constexpr double kHoldGainPerS = 0.05;
constexpr double kHoldAsternMps = 0.3;

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
  cruise_mps_ = speed_mps;
  guide();  // a guidance running now takes it at once
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
  guide();  // the heading and speed targets now, so heading_reached is meaningful at once
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

core::Result<void> Simulation::loiter(double x_m, double y_m, double radius_m) {
  if (auto r = check_goal(x_m, y_m); !r) return r;
  if (!std::isfinite(radius_m) || radius_m < kMinLoiterRadiusM || radius_m > kMaxLegM) {
    return refused_here(fmt::format("loiter radius {} m outside {} to {} m", radius_m, kMinLoiterRadiusM, kMaxLegM));
  }
  return engage({GuidanceMode::Loiter, 0.0, 0.0, x_m, y_m, radius_m});
}

core::Result<void> Simulation::hold_position() {
  if (auto r = require_network(); !r) return r;
  if (watchdog_tripped_) return refused_here("watchdog tripped: surfacing until the network restarts");
  if (!heading_target_deg_) heading_target_deg_ = compass_deg();  // keep the bow where it is
  if (auto r = engage({GuidanceMode::Hold, 0.0, 0.0, nav_.x_m(), nav_.y_m()}); !r) return r;
  reached_ = true;  // it is at its point
  return {};
}

core::Result<void> Simulation::start_rows(double x_m, double y_m, double heading_deg, double length_m, double spacing_m,
                                          double count) {
  if (auto r = require_network(); !r) return r;
  std::string why;
  auto p = protocol::make_row_pattern(x_m, y_m, heading_deg, length_m, spacing_m, count, &why);
  if (!p) return refused_here(why);
  if (p->length_m < params_.waypoint_radius_m) {
    return refused_here(
        fmt::format("row length {} m shorter than the waypoint radius, {} m", p->length_m, params_.waypoint_radius_m));
  }
  rows_ = *p;
  next_row_ = 0;
  return {};
}

core::Result<void> Simulation::next_row() {
  if (!rows_) return refused_here("no row pattern: start_rows first");
  if (next_row_ >= rows_->count) return refused_here(fmt::format("no row left: all {} rows started", rows_->count));
  const protocol::Row row = protocol::row_of(*rows_, next_row_);
  if (auto r = track(row.x0_m, row.y0_m, row.x1_m, row.y1_m); !r) return r;
  ++next_row_;
  return {};
}

bool Simulation::gps_available() const {
  return open_water() && !faults_.no_gps && heave_.depth_m <= params_.gps_max_depth_m;
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
  if (!open_water())
    return refused_here(
        "no GPS in the tank (the scenario's world; an open-water scenario has one: docs/open_water.md)");
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

// Guidance sets the heading law's and the speed law's targets once a cycle,
// from the estimate. A waypoint or a track line ends at its goal: the
// vehicle holds the goal point from then on.
void Simulation::guide() {
  if (guidance_.mode == GuidanceMode::None) return;
  if (!reached_ && guidance_.mode != GuidanceMode::Hold &&
      guidance_reached(params_, guidance_, nav_.x_m(), nav_.y_m())) {
    reached_ = true;
    event(fmt::format("guidance: {} reached at ({:.1f}, {:.1f}) m (estimated)", to_string(guidance_.mode), nav_.x_m(),
                      nav_.y_m()));
    if (guidance_.mode != GuidanceMode::Loiter)
      guidance_ = {GuidanceMode::Hold, 0.0, 0.0, guidance_.x1_m, guidance_.y1_m};
  }
  if (guidance_.mode == GuidanceMode::Hold) {
    hold();
    return;
  }
  speed_target_mps_ = cruise_speed_mps();
  GuidanceInput in{nav_.x_m(), nav_.y_m(), nav_.current_x_mps(), nav_.current_y_mps(), *speed_target_mps_};
  heading_target_deg_ = guidance_heading_deg(params_, guidance_, in);
}

// The hold law (station keeping at guidance_'s point, from the estimate):
// off station (farther than waypoint_radius_m) the heading law turns toward
// the point; always, the speed law drives along the bow toward it,
// kHoldGainPerS m/s per metre ahead, up to the cruise speed ahead or
// kHoldAsternMps astern, so the vehicle slows as it closes and backs when
// past. Within the radius the heading is left as it is.
void Simulation::hold() {
  const double dx = guidance_.x1_m - nav_.x_m();
  const double dy = guidance_.y1_m - nav_.y_m();
  const double cruise = cruise_speed_mps();
  if (std::hypot(dx, dy) > params_.waypoint_radius_m) {
    GuidanceInput in{nav_.x_m(), nav_.y_m(), nav_.current_x_mps(), nav_.current_y_mps(), cruise};
    heading_target_deg_ = guidance_heading_deg(params_, guidance_, in);
  }
  const double psi = compass_deg() * core::kRadPerDeg;
  const double ahead_m = dx * std::sin(psi) + dy * std::cos(psi);
  speed_target_mps_ = std::clamp(kHoldGainPerS * ahead_m, -std::min(kHoldAsternMps, cruise), cruise);
}

// One sub-step of surge and of the true position: water velocity along the
// true heading plus the current; the tank's walls hold the vehicle in. The
// lags are lag_fraction(h_s, ...) of the motors and the transverse thrusters.
void Simulation::move_substep(double h_s, double motor_lag, double transverse_lag) {
  const double thrust = speed_target_mps_ ? speed_thrust_n(params_, *speed_target_mps_) : 0.0;
  advance_surge(params_, thrust, params_.max_surge_thrust_n() * faults_.thrust_health, h_s, motor_lag, surge_);
  const double psi = yaw_.heading_deg * core::kRadPerDeg;
  const double cx = scenario_.world.current_x_mps;
  const double cy = scenario_.world.current_y_mps;
  // No surge (+0 exactly): 0 * sin + c is c, bit for bit, unless c is -0.
  if (plus_zero(surge_.speed_mps) && !(cx == 0.0 && std::signbit(cx)) && !(cy == 0.0 && std::signbit(cy))) {
    x_m_ += h_s * cx;
    y_m_ += h_s * cy;
  } else {
    x_m_ += h_s * (surge_.speed_mps * std::sin(psi) + cx);
    y_m_ += h_s * (surge_.speed_mps * std::cos(psi) + cy);
  }
  // Sway, to starboard (heading + 90 degrees). Skipped while at rest, so a
  // vehicle never asked to sway moves exactly as before sway existed.
  advance_sway(params_, sway_force_cmd_n_, params_.max_sway_force_n(), h_s, transverse_lag, sway_);
  advance_sway(params_, sway_model_cmd_n_, params_.max_sway_force_n(), h_s, transverse_lag, sway_model_);
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
