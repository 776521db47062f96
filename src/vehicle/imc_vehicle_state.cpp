// The simulated Phoenix as an IMC vehicle: its errors, and the state
// messages it streams (EstimatedState, VehicleState, PlanControlState,
// GpsFix), built from the Simulation as it is now.
#include <cmath>
#include <ctime>
#include <numbers>

#include <fmt/format.h>

#include "core/units.h"
#include "vehicle/imc_vehicle.h"

namespace strata::vehicle {

using imc::PlanControl;
using imc::PlanControlState;
using imc::VehicleState;

// The entities in error now: what the Phoenix itself calls a system
// problem (system_problem: a leak, a depth-cell dropout, each latched), so
// that a mission meets the same faults over IMC as over the Phoenix
// protocol. Its other faults show as they do there: weak thrusters in the
// dive, a dead altimeter as no altitude (EstimatedState alt -1), a dead GPS
// receiver as GpsFix validity 0.
std::vector<ImcVehicle::ErrorEntity> ImcVehicle::errors_now() const {
  const FaultState& f = sim_.telemetry().faults;
  std::vector<ErrorEntity> out;
  if (f.leak) out.push_back({"Leak Sensor - Nose", "leak detected"});
  if (f.depth_cell_fault) out.push_back({"Depth Sensor", "no reading"});
  return out;
}

bool ImcVehicle::in_error() const { return !errors_.empty() || abort_until_s_.has_value(); }

// A new error is the last error; any error fails the running plan (one that
// started in error fails here, a cycle after it started).
void ImcVehicle::check_errors() {
  if (abort_until_s_ && sim_.time_s() + 1e-9 >= *abort_until_s_) abort_until_s_.reset();
  auto now = errors_now();
  for (const auto& e : now) {
    const bool known = std::any_of(errors_.begin(), errors_.end(),
                                   [&](const ErrorEntity& o) { return o.entity == e.entity && o.text == e.text; });
    if (known) continue;
    last_error_ = fmt::format("{}: {}", e.entity, e.text);
    last_error_time_ = timestamp();
    log("error: " + last_error_);
  }
  if (now.empty() && !errors_.empty()) log("errors cleared");
  errors_ = std::move(now);
  if (plan_ && in_error()) {
    log(fmt::format("plan '{}' failed: {}", plan_->plan_id, last_error_));
    end_plan(PlanControl::kFailure, last_error_, PlanControlState::kLastOutcomeFailure);
  }
}

imc::EstimatedState ImcVehicle::estimated_state() const {
  const Telemetry t = sim_.telemetry();
  imc::EstimatedState s;
  s.lat = options_.origin_lat_rad;
  s.lon = options_.origin_lon_rad;
  s.x = static_cast<float>(t.y_m);  // north
  s.y = static_cast<float>(t.x_m);  // east
  const double depth = depth_now();
  s.z = static_cast<float>(depth);
  double psi = t.heading_deg * core::kRadPerDeg;
  if (psi > std::numbers::pi) psi -= 2.0 * std::numbers::pi;
  s.psi = static_cast<float>(psi);
  s.u = static_cast<float>(t.speed_mps);
  s.v = static_cast<float>(sim_.sway().speed_mps);
  s.w = static_cast<float>(t.w_mps);
  s.vx = static_cast<float>(t.speed_mps * std::cos(psi));
  s.vy = static_cast<float>(t.speed_mps * std::sin(psi));
  s.vz = static_cast<float>(t.w_mps);
  s.r = static_cast<float>(t.yaw_rate_dps * core::kRadPerDeg);
  s.depth = static_cast<float>(depth);
  s.alt = t.altitude_m ? static_cast<float>(*t.altitude_m) : -1.0f;
  return s;
}

imc::VehicleState ImcVehicle::vehicle_state() const {
  const Telemetry t = sim_.telemetry();
  VehicleState s;
  s.op_mode = in_error() ? VehicleState::kOpModeError
              : plan_    ? VehicleState::kOpModeManeuver
                         : VehicleState::kOpModeService;
  s.error_count = static_cast<std::uint8_t>(std::min<std::size_t>(errors_.size(), 255));
  for (const auto& e : errors_) {
    if (!s.error_ents.empty()) s.error_ents += ",";
    s.error_ents += e.entity;
  }
  s.maneuver_type = plan_ ? imc::FollowReference::kId : imc::kNullId;
  s.maneuver_stime = plan_ ? kImcEpochS + plan_->start_s : -1.0;
  s.maneuver_eta = 0xFFFF;
  std::uint32_t loops = 0;
  if (t.mode != ControlMode::Idle) loops |= VehicleState::kLoopDepth;
  if (t.heading_setpoint_deg) loops |= VehicleState::kLoopYaw;
  if (t.guidance != GuidanceMode::None) loops |= VehicleState::kLoopPath;
  if (t.speed_setpoint_mps && *t.speed_setpoint_mps > 0) loops |= VehicleState::kLoopSpeed;
  s.control_loops = loops;
  s.last_error = last_error_;
  s.last_error_time = last_error_.empty() ? -1.0 : last_error_time_;
  return s;
}

imc::PlanControlState ImcVehicle::plan_control_state() const {
  PlanControlState s;
  s.state = in_error() ? PlanControlState::kStateBlocked
            : plan_    ? PlanControlState::kStateExecuting
                       : PlanControlState::kStateReady;
  s.plan_id = plan_ ? plan_->plan_id : last_plan_id_;
  s.plan_eta = -1;
  s.plan_progress = -1.0f;
  s.man_id = plan_ ? plan_->maneuver_id : std::string();
  s.man_type = plan_ ? imc::FollowReference::kId : imc::kNullId;
  s.man_eta = -1;
  s.last_outcome = last_outcome_;
  return s;
}

// A fix at the surface (depth < 0.2 m) in open water with a working
// receiver: the true position; nothing valid otherwise.
imc::GpsFix ImcVehicle::gps_fix() const {
  const Telemetry t = sim_.telemetry();
  imc::GpsFix g;
  g.type = imc::GpsFix::kTypeStandalone;
  if (!t.open_water || t.faults.no_gps || !(t.depth_m < 0.2)) return g;
  const double ts = timestamp();
  const auto whole = static_cast<std::time_t>(std::floor(ts));
  std::tm utc{};
  gmtime_r(&whole, &utc);
  g.validity = 0x1FF;
  g.utc_year = static_cast<std::uint16_t>(utc.tm_year + 1900);
  g.utc_month = static_cast<std::uint8_t>(utc.tm_mon + 1);
  g.utc_day = static_cast<std::uint8_t>(utc.tm_mday);
  g.utc_time = static_cast<float>(utc.tm_hour * 3600 + utc.tm_min * 60 + utc.tm_sec + (ts - std::floor(ts)));
  const auto [lat, lon] = to_lat_lon(t.true_x_m, t.true_y_m);
  g.lat = lat;
  g.lon = lon;
  g.satellites = 9;
  g.cog = static_cast<float>(t.heading_deg * core::kRadPerDeg);
  g.sog = static_cast<float>(t.speed_mps);
  g.hdop = 0.9f;
  g.vdop = 1.4f;
  g.hacc = static_cast<float>(sim_.params().gps_noise_m);
  g.vacc = 3.0f;
  return g;
}

// The estimate's horizontal 1-sigma is sqrt(var_x + var_y), the two equal.
imc::NavigationUncertainty ImcVehicle::navigation_uncertainty() const {
  const double sd = sim_.navigator().position_sd_m();
  imc::NavigationUncertainty u;
  u.x = static_cast<float>(sd * sd / 2.0);
  u.y = u.x;
  return u;
}

}  // namespace strata::vehicle
