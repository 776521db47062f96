#include "vehicle/simulation.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <fmt/format.h>

#include "vehicle/depth_controller.h"
#include "vehicle/drag_axis.h"
#include "vehicle/time_compare.h"

namespace strata::vehicle {

std::string_view to_string(ControlMode mode) {
  switch (mode) {
    case ControlMode::Idle: return "idle";
    case ControlMode::Depth: return "depth";
    case ControlMode::Surface: return "surface";
  }
  return "?";
}

namespace {

core::Error refused(std::string message) { return core::make_error(core::ErrorCode::InvalidInput, std::move(message)); }

}  // namespace

Simulation::Simulation(VehicleParams params, Scenario scenario)
    : params_(params),
      scenario_(std::move(scenario)),
      cell_(params_.depth_noise_m, scenario_.seed),
      filter_(params_.filter_alpha, params_.filter_beta, params_.cycle_s),
      sonar_(params_, scenario_.seed, scenario_.target, !scenario_.world.open_water),
      nav_(params_, 0.0, 0.0, 0.0),
      // Noise streams of their own, so the depth cell's and the sonar's
      // sequences are the same as before the horizontal plane existed.
      gps_x_noise_(params_.gps_noise_m, scenario_.seed ^ 0x9e3779b97f4a7c15ULL),
      gps_y_noise_(params_.gps_noise_m, scenario_.seed ^ 0xbf58476d1ce4e5b9ULL),
      altimeter_noise_(params_.altimeter_noise_m, scenario_.seed ^ 0x94d049bb133111ebULL),
      altitude_floor_m_(params_.altitude_floor_m),
      fault_applied_(scenario_.faults.size(), false) {
  place_vehicle();
  apply_faults();
  sense();
}

void Simulation::place_vehicle() {
  yaw_.heading_deg = wrap_heading_deg(scenario_.vehicle_heading_deg);
  if (open_water()) {
    x_m_ = scenario_.vehicle_x_m.value_or(0.0);
    y_m_ = scenario_.vehicle_y_m.value_or(0.0);
    nav_ = Navigator(params_, x_m_, y_m_, params_.nav_initial_sd_m);
    return;
  }
  const double want_x = scenario_.vehicle_x_m.value_or(params_.tank_length_x_m / 2.0);
  const double want_y = scenario_.vehicle_y_m.value_or(params_.tank_width_y_m / 2.0);
  x_m_ = std::clamp(want_x, 0.0, params_.tank_length_x_m);
  y_m_ = std::clamp(want_y, 0.0, params_.tank_width_y_m);
  if (x_m_ != want_x || y_m_ != want_y) {
    event(
        fmt::format("scenario: vehicle at ({}, {}) m is outside the {} x {} m tank: placed at "
                    "({}, {}) m",
                    want_x, want_y, params_.tank_length_x_m, params_.tank_width_y_m, x_m_, y_m_));
  }
  nav_ = Navigator(params_, x_m_, y_m_, 0.0);
  if (const auto& t = scenario_.target; t && std::hypot(x_m_ - t->x_m, y_m_ - t->y_m) <= t->radius_m) {
    event("scenario: the vehicle is inside the target: the sonar cannot see it");
  }
}

core::Result<void> Simulation::require_network() const {
  if (!network_up_) return refused("network not started");
  return {};
}

core::Result<void> Simulation::start_network() {
  network_up_ = true;
  watchdog_tripped_ = false;
  return {};
}

core::Result<void> Simulation::shutdown_network() {
  network_up_ = false;
  mode_ = ControlMode::Idle;
  heading_target_deg_.reset();
  speed_target_mps_.reset();
  sway_target_mps_.reset();
  guidance_ = {};
  sonar_.stop();
  return {};
}

core::Result<void> Simulation::set_setpoint(double depth_m, double timeout_s) {
  if (auto r = require_network(); !r) return r;
  const double deepest = open_water() ? params_.max_depth_m : params_.tank_depth_m;
  if (!std::isfinite(depth_m) || depth_m < 0.0 || depth_m > deepest) {
    return refused(fmt::format("setpoint depth {} m outside the {} (0 to {} m)", depth_m,
                               open_water() ? "vehicle's range" : "tank", deepest));
  }
  if (!std::isfinite(timeout_s) || timeout_s <= 0.0) {
    return refused(fmt::format("setpoint timeout {} s must be positive", timeout_s));
  }
  loaded_ = Setpoint{depth_m, timeout_s};
  return {};
}

core::Result<void> Simulation::start_depth_filter() {
  if (auto r = require_network(); !r) return r;
  if (!filter_.on()) {
    filter_.start();
    filter_.update(reading_m_);  // initialise from the current reading, if any
  }
  return {};
}

core::Result<void> Simulation::submerge() {
  if (auto r = require_network(); !r) return r;
  if (!loaded_) return refused("no setpoint loaded");
  if (!filter_.on()) return refused("depth filter is off");
  if (watchdog_tripped_) return refused("watchdog tripped: surfacing until the network restarts");
  active_setpoint_m_ = loaded_->depth_m;
  mode_ = ControlMode::Depth;
  return {};
}

core::Result<void> Simulation::start_timer() {
  if (auto r = require_network(); !r) return r;
  if (!loaded_) return refused("no setpoint loaded");
  timer_ = Timer{time_s(), loaded_->timeout_s};
  return {};
}

core::Result<void> Simulation::set_timer(double seconds) {
  if (auto r = require_network(); !r) return r;
  if (!std::isfinite(seconds) || seconds <= 0.0) {
    return refused(fmt::format("timer limit {} s must be positive", seconds));
  }
  timer_ = Timer{time_s(), seconds};
  return {};
}

core::Result<void> Simulation::surface() {
  if (auto r = require_network(); !r) return r;
  active_setpoint_m_ = 0.0;
  mode_ = ControlMode::Surface;
  return {};
}

core::Result<void> Simulation::set_heading(double heading_deg) {
  if (auto r = require_network(); !r) return r;
  if (!std::isfinite(heading_deg) || heading_deg < 0.0 || heading_deg > 360.0) {
    return refused(fmt::format("heading {} deg outside 0 to 360 deg", heading_deg));
  }
  if (watchdog_tripped_) return refused("watchdog tripped: surfacing until the network restarts");
  heading_target_deg_ = wrap_heading_deg(heading_deg);
  return {};
}

core::Result<void> Simulation::start_sonar() {
  if (auto r = require_network(); !r) return r;
  sonar_.start();
  return {};
}

core::Result<void> Simulation::stop_sonar() {
  if (auto r = require_network(); !r) return r;
  sonar_.stop();
  return {};
}

void Simulation::watchdog_trip(std::string_view reason) {
  active_setpoint_m_ = 0.0;
  mode_ = ControlMode::Surface;
  heading_target_deg_.reset();
  speed_target_mps_.reset();
  sway_target_mps_.reset();
  guidance_ = {};
  if (watchdog_tripped_) return;
  watchdog_tripped_ = true;
  event(fmt::format("watchdog: {}: surfacing", reason));
}

bool Simulation::depth_reached() const {
  if (mode_ != ControlMode::Depth || !active_setpoint_m_ || !filter_.ready()) return false;
  return std::abs(filter_.depth_m() - *active_setpoint_m_) < params_.depth_tolerance_m &&
         std::abs(filter_.rate_mps()) < params_.settle_rate_mps;
}

bool Simulation::heading_reached() const {
  if (!heading_target_deg_) return false;
  return std::abs(heading_error_deg(yaw_.heading_deg, *heading_target_deg_)) < params_.heading_tolerance_deg &&
         std::abs(yaw_.rate_dps) < params_.heading_settle_dps;
}

bool Simulation::time_out() const { return timer_ && time_reached(time_s(), timer_->start_s + timer_->timeout_s); }

bool Simulation::surface_reached() const {
  const auto z = depth_estimate();
  return z && *z <= params_.surface_depth_m;
}

std::optional<double> Simulation::depth_estimate() const {
  if (filter_.ready()) return filter_.depth_m();
  if (filter_.on()) return std::nullopt;  // started, no reading yet
  return reading_m_;
}

double Simulation::control() const {
  switch (mode_) {
    case ControlMode::Idle: return 0.0;
    case ControlMode::Depth:
      if (!filter_.ready() || !active_setpoint_m_) return 0.0;
      return sliding_mode_thrust(params_, filter_.depth_m(), filter_.rate_mps(), *active_setpoint_m_);
    case ControlMode::Surface: return surface_thrust(params_, depth_estimate());
  }
  return 0.0;
}

void Simulation::step() {
  thrust_cmd_n_ = control();
  // The Execution level's own model of its thrusters: the lag, at nominal
  // strength (it cannot know they are weak).
  thrust_model_n_ +=
      (thrust_cmd_n_ - thrust_model_n_) * lag_fraction(params_.cycle_s, std::max(params_.thruster_lag_s, 1e-9));
  const double limit = params_.max_total_thrust_n() * faults_.thrust_health;
  const HeaveContact contact = advance_heave(params_, thrust_cmd_n_, limit, bottom_m(), heave_);
  guide();
  advance_yaw_and_sonar();
  ++cycle_;
  navigate();
  if (contact.bottom && !at_bottom_) {
    event(open_water()
              ? fmt::format("seabed: vehicle on the bottom at {:.2f} m, ({:.1f}, {:.1f}) m", heave_.depth_m, x_m_, y_m_)
              : fmt::format("tank: vehicle on the bottom at {:.2f} m", heave_.depth_m));
  }
  at_bottom_ = contact.bottom;
  apply_faults();
  sense();
}

// The yaw dynamics sub-step by sub-step, so the sonar pings at sub-step
// resolution with the heading of its moment. (Heave has run for the whole
// cycle already; the sonar does not depend on depth.)
void Simulation::advance_yaw_and_sonar() {
  moment_cmd_nm_ =
      heading_target_deg_ ? heading_moment(params_, compass_deg(), yaw_.rate_dps, *heading_target_deg_) : 0.0;
  const double limit = params_.max_yaw_moment_nm() * faults_.thrust_health;
  // Sway gets the transverse thrust the heading law's moment leaves (sway.h);
  // the vehicle's own model assumes nominal thrusters.
  const double sway_asked = sway_target_mps_ ? sway_force_n(params_, *sway_target_mps_) : 0.0;
  const double sway_limit =
      sway_force_limit_n(params_, std::clamp(moment_cmd_nm_, -limit, limit), faults_.thrust_health);
  sway_force_cmd_n_ = std::clamp(sway_asked, -sway_limit, sway_limit);
  const double nominal = params_.max_yaw_moment_nm();
  const double model_limit = sway_force_limit_n(params_, std::clamp(moment_cmd_nm_, -nominal, nominal), 1.0);
  sway_model_cmd_n_ = std::clamp(sway_asked, -model_limit, model_limit);
  const double h = params_.cycle_s / params_.substeps;
  const double transverse_lag = lag_fraction(h, params_.transverse_lag_s);
  const double motor_lag = lag_fraction(h, params_.motor_lag_s);
  for (int i = 1; i <= params_.substeps; ++i) {
    advance_yaw(params_, moment_cmd_nm_, limit, h, transverse_lag, yaw_);
    move_substep(h, motor_lag, transverse_lag);
    const double t = (static_cast<double>(cycle_) + static_cast<double>(i) / params_.substeps) * params_.cycle_s;
    sonar_.substep(t, pose());
  }
}

std::uint64_t Simulation::advance(double seconds) {
  if (!(seconds > 0.0)) return 0;
  const auto n = static_cast<std::uint64_t>(std::llround(seconds / params_.cycle_s));
  for (std::uint64_t i = 0; i < n; ++i) step();
  return n;
}

void Simulation::apply_faults() {
  const double t = time_s();
  for (std::size_t i = 0; i < scenario_.faults.size(); ++i) {
    const Fault& f = scenario_.faults[i];
    if (fault_applied_[i] || !time_reached(t, f.at_s)) continue;
    fault_applied_[i] = true;
    switch (f.kind) {
      case FaultKind::WeakThrusters:
        faults_.thrust_health = f.health;
        event(fmt::format("fault: thrusters weakened to {:.0f}% of nominal thrust", 100.0 * f.health));
        break;
      case FaultKind::Leak:
        faults_.leak = true;
        event("fault: leak started (system problem)");
        break;
      case FaultKind::SensorDropout:
        dropout_until_s_ = std::max(dropout_until_s_.value_or(0.0), f.at_s + *f.duration_s);
        faults_.sensor_dropout = true;
        faults_.depth_cell_fault = true;
        event(fmt::format("fault: depth cell dropout for {:.1f} s (system problem)", *f.duration_s));
        break;
      case FaultKind::LinkLoss:
        event(f.duration_s ? fmt::format("fault: link lost for {:.1f} s", *f.duration_s)
                           : std::string("fault: link lost for good"));
        break;
      case FaultKind::CompassBias:
        faults_.compass_bias_deg = f.bias_deg;
        event(fmt::format("fault: compass reads {:+.1f} deg off", f.bias_deg));
        break;
      case FaultKind::AltimeterDead:
        faults_.altimeter_dead = true;
        event("fault: altimeter dead");
        break;
      case FaultKind::NoGps:
        faults_.no_gps = true;
        event("fault: no GPS fix");
        break;
    }
  }
  if (dropout_until_s_ && time_reached(t, *dropout_until_s_)) {
    dropout_until_s_.reset();
    faults_.sensor_dropout = false;
    event("fault: depth cell readings back");
  }
  const bool lost = scenario_.link_lost(t);
  if (faults_.link_lost && !lost) event("fault: link restored");
  faults_.link_lost = lost;
}

void Simulation::sense() {
  reading_m_ = cell_.sample(heave_.depth_m, faults_.sensor_dropout);
  filter_.update(reading_m_, expected_accel_mps2());
  const double altitude = bottom_m() - heave_.depth_m;
  const auto echo = altimeter_noise_.sample(altitude, faults_.altimeter_dead || altitude > params_.altimeter_range_m);
  altitude_m_ = echo ? std::optional<double>(std::max(0.0, *echo)) : std::nullopt;
}

// The filter's prediction uses the heave model (heave.h) under the thrust
// the Execution level believes it has: it knows what it commanded, not what
// the thrusters gave (weak thrusters show up as residuals the filter corrects).
double Simulation::expected_accel_mps2() const {
  if (!filter_.ready()) return 0.0;
  const double w = filter_.rate_mps();
  return (thrust_model_n_ - params_.buoyancy_n - params_.drag_coeff * w * std::abs(w)) / params_.total_mass_kg();
}

void Simulation::event(std::string text) { events_.push_back({time_s(), std::move(text)}); }

std::vector<Event> Simulation::take_events() { return std::exchange(events_, {}); }

Telemetry Simulation::telemetry() const {
  Telemetry t;
  t.time_s = time_s();
  t.depth_m = heave_.depth_m;
  t.w_mps = heave_.w_mps;
  t.measured_depth_m = reading_m_;
  if (filter_.ready()) {
    t.filtered_depth_m = filter_.depth_m();
    t.rate_mps = filter_.rate_mps();
  }
  t.thrust_n = heave_.thrust_n;
  t.thrust_cmd_n = thrust_cmd_n_;
  if (mode_ != ControlMode::Idle) t.setpoint_m = active_setpoint_m_;
  t.heading_deg = yaw_.heading_deg;
  t.yaw_rate_dps = yaw_.rate_dps;
  t.yaw_moment_nm = yaw_.moment_nm;
  t.yaw_moment_cmd_nm = moment_cmd_nm_;
  t.heading_setpoint_deg = heading_target_deg_;
  t.x_m = nav_.x_m();
  t.y_m = nav_.y_m();
  t.true_x_m = x_m_;
  t.true_y_m = y_m_;
  t.position_sd_m = nav_.position_sd_m();
  t.speed_mps = surge_.speed_mps;
  t.speed_setpoint_mps = speed_target_mps_;
  t.altitude_m = altitude_m_;
  t.guidance = guidance_.mode;
  t.open_water = open_water();
  t.sonar_on = sonar_.on();
  t.filter_on = filter_.on();
  t.mode = mode_;
  t.network_up = network_up_;
  t.watchdog_tripped = watchdog_tripped_;
  t.faults = faults_;
  return t;
}

}  // namespace strata::vehicle
