// The simulated Phoenix as an IMC vehicle (imc_vehicle.h states the
// decisions): plans, References, Abort, errors, and the streams.
#include "vehicle/imc_vehicle.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>
#include <variant>

#include <fmt/format.h>

#include "core/units.h"

namespace strata::vehicle {
namespace {

using imc::FollowRefState;
using imc::PlanControl;
using imc::PlanControlState;
using imc::VehicleState;

// Simulated seconds as a count of cycles, for the periodic streams: exact
// where t / cycle is not.
std::uint64_t every(double period_s, double cycle_s) {
  return std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::llround(period_s / cycle_s)));
}

std::string hex_id(std::uint16_t id) { return fmt::format("0x{:04X}", id); }

struct FollowPlan {
  imc::FollowReference manoeuvre;
  std::string maneuver_id;
};

// The FollowReference of a plan that is one FollowReference manoeuvre, or why not.
std::variant<FollowPlan, std::string> follow_reference_of(const PlanControl& pc) {
  const auto* spec = pc.arg.get_if<imc::PlanSpecification>();
  if (!spec) {
    return std::string(pc.arg.empty() ? "no plan given (stored plans are not kept here)"
                                      : "the argument is not a PlanSpecification");
  }
  if (spec->maneuvers.size() != 1) {
    return fmt::format("only a plan of one FollowReference manoeuvre is supported ({} manoeuvres)",
                       spec->maneuvers.size());
  }
  const auto* fr = spec->maneuvers.front().data.get_if<imc::FollowReference>();
  if (!fr) return std::string("only a FollowReference manoeuvre is supported");
  return FollowPlan{*fr, spec->maneuvers.front().maneuver_id};
}

}  // namespace

ImcVehicle::ImcVehicle(Simulation& sim, ImcVehicleOptions options) : sim_(sim), options_(std::move(options)) {
  (void)sim_.start_network();
  flush_events();
}

void ImcVehicle::log(const std::string& line) const {
  // A controller repeats its Reference twice a second, and with it whatever
  // the vehicle had to say about it (a point clamped to the tank, a source
  // ignored): a line the same as the last is counted, not written again.
  if (line == last_line_) {
    ++repeats_;
    return;
  }
  if (repeats_ > 0 && options_.log) options_.log(fmt::format("(the line before, {} more times)", repeats_));
  last_line_ = line;
  repeats_ = 0;
  if (options_.log) options_.log(fmt::format("{:.1f} s: {}", sim_.time_s(), line));
}

void ImcVehicle::flush_events() {
  for (const auto& ev : sim_.take_events()) {
    if (options_.log) options_.log(fmt::format("{:.1f} s: {}", ev.time_s, ev.text));
  }
}

void ImcVehicle::send(imc::Message m, std::uint16_t dst, std::uint8_t dst_ent) {
  outbox_.push_back({std::move(m), dst, dst_ent});
}

std::vector<ImcOutgoing> ImcVehicle::take_outbox() { return std::exchange(outbox_, {}); }

// ---- coordinates ------------------------------------------------------------

std::pair<double, double> ImcVehicle::to_lat_lon(double x_east_m, double y_north_m) const {
  return {options_.origin_lat_rad + y_north_m / kEarthRadiusM,
          options_.origin_lon_rad + x_east_m / (kEarthRadiusM * std::cos(options_.origin_lat_rad))};
}

std::pair<double, double> ImcVehicle::to_plan(double lat_rad, double lon_rad) const {
  return {(lon_rad - options_.origin_lon_rad) * kEarthRadiusM * std::cos(options_.origin_lat_rad),
          (lat_rad - options_.origin_lat_rad) * kEarthRadiusM};
}

// ---- what comes in ------------------------------------------------------------

void ImcVehicle::receive(const imc::Header& header, const imc::Message& message) {
  if (const auto* pc = std::get_if<PlanControl>(&message)) {
    on_plan_control(header, *pc);
  } else if (const auto* ref = std::get_if<imc::Reference>(&message)) {
    on_reference(header, *ref);
  } else if (std::holds_alternative<imc::Abort>(message)) {
    on_abort(header);
  } else if (const auto* set = std::get_if<imc::SetEntityParameters>(&message)) {
    on_entity_parameters(*set);
  }
}

// The scanning sonar is the payload "Sidescan": Active = true / false
// switches it, as DUNE switches its payloads. Other entities and
// parameters are not the Phoenix's: logged and left.
void ImcVehicle::on_entity_parameters(const imc::SetEntityParameters& set) {
  for (const imc::EntityParameter& param : set.params) {
    if (set.name != "Sidescan" || param.name != "Active" || (param.value != "true" && param.value != "false")) {
      log(fmt::format("SetEntityParameters {}: {} = {} ignored (only Sidescan's Active)", set.name, param.name,
                      param.value));
      continue;
    }
    auto r = param.value == "true" ? sim_.start_sonar() : sim_.stop_sonar();
    if (!r) log(fmt::format("Sidescan Active = {} refused: {}", param.value, r.error().message));
  }
}

void ImcVehicle::reply(const imc::Header& to, const PlanControl& request, std::uint8_t type, std::string info) {
  PlanControl r;
  r.type = type;
  r.op = request.op;
  r.request_id = request.request_id;
  r.plan_id = request.plan_id;
  r.info = std::move(info);
  send(std::move(r), to.src, to.src_ent);
}

void ImcVehicle::on_plan_control(const imc::Header& h, const PlanControl& pc) {
  if (pc.type != PlanControl::kRequest) return;  // a reply: not for a vehicle
  if (h.dst != options_.imc_id && h.dst != imc::kAnyVehicle) {
    ++counts_.requests_ignored;
    log(fmt::format("PlanControl from {} addressed to {}: ignored", hex_id(h.src), hex_id(h.dst)));
    return;
  }
  switch (pc.op) {
    case PlanControl::kStart: start_plan(h, pc); return;
    case PlanControl::kStop:
      if (plan_) {
        log(fmt::format("plan '{}' stopped by {}", plan_->plan_id, hex_id(h.src)));
        last_plan_id_ = plan_->plan_id;
        last_outcome_ = PlanControlState::kLastOutcomeNone;
        plan_.reset();
        loops_off();
      }
      reply(h, pc, PlanControl::kSuccess, "plan stopped");
      return;
    default:
      reply(h, pc, PlanControl::kFailure, fmt::format("operation {} is not supported by this vehicle", pc.op));
      return;
  }
}

void ImcVehicle::start_plan(const imc::Header& h, const PlanControl& pc) {
  auto fr = follow_reference_of(pc);
  if (const auto* why = std::get_if<std::string>(&fr)) {
    log(fmt::format("plan '{}' from {} refused: {}", pc.plan_id, hex_id(h.src), *why));
    reply(h, pc, PlanControl::kFailure, *why);
    return;
  }
  const auto& f = std::get<FollowPlan>(fr).manoeuvre;
  if (plan_) log(fmt::format("plan '{}' replaced", plan_->plan_id));
  // A new plan lifts an Abort's surfacing (the Phoenix's network restart).
  (void)sim_.start_network();
  Plan p;
  p.plan_id = pc.plan_id;
  p.maneuver_id = std::get<FollowPlan>(fr).maneuver_id;
  p.request_id = pc.request_id;
  p.requester = h.src;
  p.requester_ent = h.src_ent;
  p.control_src = f.control_src;
  p.control_ent = f.control_ent;
  p.timeout_s = std::isfinite(f.timeout) && f.timeout > 0 ? f.timeout : 0.0;
  p.start_s = sim_.time_s();
  p.last_reference_s = sim_.time_s();
  plan_ = std::move(p);
  log(fmt::format("plan '{}' started by {}: references from {}/{}, timeout {} s", pc.plan_id, hex_id(h.src),
                  hex_id(f.control_src), f.control_ent, plan_->timeout_s));
  reply(h, pc, PlanControl::kSuccess, "plan loaded");
  reply(h, pc, PlanControl::kSuccess, "executing maneuver");
  send(plan_control_state());
  send(vehicle_state());
  send(follow_ref_state(FollowRefState::kStateWait));
}

void ImcVehicle::on_reference(const imc::Header& h, const imc::Reference& ref) {
  if (!plan_) {
    ++counts_.references_ignored;
    log(fmt::format("Reference from {} ignored: no plan executes", hex_id(h.src)));
    return;
  }
  if ((plan_->control_src != imc::kNullId && h.src != plan_->control_src) ||
      (plan_->control_ent != imc::kAnyEntity && h.src_ent != plan_->control_ent)) {
    ++counts_.references_ignored;
    log(fmt::format("Reference from {}/{} ignored: the plan follows {}/{}", hex_id(h.src), h.src_ent,
                    hex_id(plan_->control_src), plan_->control_ent));
    return;
  }
  ++counts_.references;
  Plan& p = *plan_;
  p.last_reference_s = sim_.time_s();
  p.reference = ref;
  if (ref.flags & imc::Reference::kFlagManDone) {
    send(follow_ref_state(follow_state()));
    log(fmt::format("plan '{}' completed (MANDONE)", p.plan_id));
    end_plan(PlanControl::kSuccess, "plan completed", PlanControlState::kLastOutcomeSuccess);
    return;
  }
  const VehicleParams& params = sim_.params();
  if ((ref.flags & imc::Reference::kFlagSpeed) && ref.speed) {
    double v = ref.speed->value;
    if (ref.speed->speed_units == imc::DesiredSpeed::kSpeedUnitsPercentage) {
      v = params.top_speed_mps() * v / 100.0;
    } else if (ref.speed->speed_units != imc::DesiredSpeed::kSpeedUnitsMetersPs) {
      log("Reference speed in RPM ignored (m/s or percent only)");
      v = p.speed_mps;
    }
    if (!std::isfinite(v)) v = p.speed_mps;
    const double clamped = std::clamp(v, 0.0, params.top_speed_mps());
    if (clamped != v) {
      ++counts_.clamped;
      log(fmt::format("Reference speed {:.3g} m/s clamped to {:.3g} m/s", v, clamped));
    }
    p.speed_mps = clamped;
  } else if (p.speed_mps == 0.0 && !p.goal) {
    p.speed_mps = params.cruise_speed_mps;  // a first goal without a speed: cruise
  }
  if (ref.flags & imc::Reference::kFlagLocation) {
    auto [x, y] = to_plan(ref.lat, ref.lon);
    if (!sim_.open_water()) {
      const double cx = std::clamp(x, 0.0, params.tank_length_x_m);
      const double cy = std::clamp(y, 0.0, params.tank_width_y_m);
      if (cx != x || cy != y) {
        ++counts_.clamped;
        log(fmt::format("Reference point ({:.1f}, {:.1f}) m outside the tank: moved to ({:.1f}, {:.1f}) m", x, y, cx,
                        cy));
      }
      x = cx;
      y = cy;
    }
    const auto& nav = sim_.navigator();
    if (!std::isfinite(x) || !std::isfinite(y) || std::hypot(x - nav.x_m(), y - nav.y_m()) > kMaxLegM) {
      log(fmt::format("Reference point ({:.0f}, {:.0f}) m refused: farther than {:.0f} m", x, y, kMaxLegM));
    } else {
      p.goal = std::make_pair(x, y);
      // A point the vehicle is at already (within the guidance's radius): arrived.
      p.holding = std::hypot(x - nav.x_m(), y - nav.y_m()) < params.waypoint_radius_m;
    }
  } else if (!p.goal) {
    // No location yet: hold where the vehicle is (DUNE would reuse an old one).
    p.goal = std::make_pair(sim_.navigator().x_m(), sim_.navigator().y_m());
  }
  if ((ref.flags & imc::Reference::kFlagZ) && ref.z) {
    if (ref.z->z_units != imc::DesiredZ::kZUnitsDepth) {
      log(fmt::format("Reference z in units {} ignored (depth only)", ref.z->z_units));
    } else if (std::isfinite(ref.z->value)) {
      const double deepest = sim_.open_water() ? params.max_depth_m : params.tank_depth_m;
      const double z = std::clamp(static_cast<double>(ref.z->value), 0.0, deepest);
      if (z != ref.z->value) {
        ++counts_.clamped;
        log(fmt::format("Reference depth {:.2f} m clamped to {:.2f} m", ref.z->value, z));
      }
      p.depth_m = z;
      const auto r = z > 0.0 ? sim_.goto_depth(z) : sim_.surface();
      if (!r) log(fmt::format("Reference depth {:.2f} m not taken: {}", z, r.error().message));
    }
  }
  drive();
  send(follow_ref_state(follow_state()));
}

void ImcVehicle::on_abort(const imc::Header& h) {
  if (h.dst != options_.imc_id && h.dst != imc::kAnyVehicle) {
    ++counts_.requests_ignored;
    log(fmt::format("Abort from {} addressed to {}: ignored", hex_id(h.src), hex_id(h.dst)));
    return;
  }
  log(fmt::format("Abort from {}", hex_id(h.src)));
  abort_until_s_ = sim_.time_s() + kAbortErrorS;
  last_error_ = "got abort request";
  last_error_time_ = timestamp();
  if (plan_) {
    Plan p = std::move(*plan_);
    plan_.reset();
    last_plan_id_ = p.plan_id;
    last_outcome_ = PlanControlState::kLastOutcomeFailure;
    PlanControl r;
    r.type = PlanControl::kFailure;
    r.op = PlanControl::kStart;
    r.request_id = p.request_id;
    r.plan_id = p.plan_id;
    r.info = "got abort request";
    send(std::move(r), p.requester, p.requester_ent);
  }
  // Unlike DUNE, the Phoenix surfaces: its watchdog's surfacing.
  sim_.watchdog_trip("got abort request");
  flush_events();
  send(vehicle_state());
  send(plan_control_state());
}

void ImcVehicle::end_plan(std::uint8_t type, std::string info, std::uint8_t outcome) {
  if (!plan_) return;
  Plan p = std::move(*plan_);
  plan_.reset();
  last_plan_id_ = p.plan_id;
  last_outcome_ = outcome;
  PlanControl r;
  r.type = type;
  r.op = PlanControl::kStart;
  r.request_id = p.request_id;
  r.plan_id = p.plan_id;
  r.info = std::move(info);
  send(std::move(r), p.requester, p.requester_ent);
  loops_off();
  send(plan_control_state());
  send(vehicle_state());
}

// Every control loop off, as DUNE's SERVICE: the Simulation's network
// restarted (thrusters off, guidance and heading law dropped).
void ImcVehicle::loops_off() {
  (void)sim_.shutdown_network();
  (void)sim_.start_network();
}

// ---- each cycle -----------------------------------------------------------------

void ImcVehicle::step() {
  sim_.step();
  flush_events();
  check_errors();
  if (plan_ && plan_->timeout_s > 0 && sim_.time_s() + 1e-9 >= plan_->last_reference_s + plan_->timeout_s) {
    log(fmt::format("plan '{}': no Reference for {} s", plan_->plan_id, plan_->timeout_s));
    send(follow_ref_state(FollowRefState::kStateTimeout));
    end_plan(PlanControl::kFailure, "reference source timed out", PlanControlState::kLastOutcomeFailure);
  }
  if (plan_) drive();
  const double cycle_s = sim_.params().cycle_s;
  const std::uint64_t c = sim_.cycle();
  // The uncertainty first: an ask answered at this EstimatedState sees it.
  send(navigation_uncertainty());
  send(estimated_state());
  if (c % every(0.5, cycle_s) == 0) {
    send(vehicle_state());
    send(plan_control_state());
  }
  if (c % every(1.0, cycle_s) == 0) {
    send(gps_fix());
    send(imc::Heartbeat{});
  }
}

// Follows the goal: the guidance toward it at the plan's speed until it is
// reached, then the motors stop and the vehicle holds, until it drifts off.
void ImcVehicle::drive() {
  Plan& p = *plan_;
  if (!p.goal || sim_.watchdog_tripped()) return;
  const auto [gx, gy] = *p.goal;
  if (p.speed_mps <= 0.0) {
    if (!p.holding || sim_.guidance().mode != GuidanceMode::None) (void)sim_.stop();
    p.holding = true;
    return;
  }
  const double d = horizontal_distance_m();
  if (p.holding) {
    if (d <= kHoldRadiusM) {
      if (sim_.guidance().mode != GuidanceMode::None) (void)sim_.stop();
      return;
    }
    p.holding = false;
  } else if (sim_.guidance().mode != GuidanceMode::None && sim_.waypoint_reached()) {
    // The Phoenix's guidance ended at the point (it holds it): this vehicle
    // holds with its own, looser, station keeping below.
    (void)sim_.stop();
    p.holding = true;
    return;
  }
  const Guidance& g = sim_.guidance();
  const bool engaged = g.mode == GuidanceMode::Waypoint && g.x1_m == gx && g.y1_m == gy;
  if (engaged && sim_.telemetry().speed_setpoint_mps == p.speed_mps) return;
  if (auto r = sim_.set_speed(p.speed_mps); !r) log(fmt::format("set_speed refused: {}", r.error().message));
  if (auto r = sim_.goto_xy(gx, gy); !r)
    log(fmt::format("goto ({:.1f}, {:.1f}) m refused: {}", gx, gy, r.error().message));
}

double ImcVehicle::horizontal_distance_m() const {
  if (!plan_ || !plan_->goal) return 0.0;
  const auto& nav = sim_.navigator();
  return std::hypot(plan_->goal->first - nav.x_m(), plan_->goal->second - nav.y_m());
}

double ImcVehicle::depth_now() const {
  const Telemetry t = sim_.telemetry();
  if (t.filtered_depth_m) return std::max(0.0, *t.filtered_depth_m);
  if (t.measured_depth_m) return std::max(0.0, *t.measured_depth_m);
  return t.depth_m;
}

std::uint8_t ImcVehicle::proximity() const {
  std::uint8_t prox = 0;
  if (!plan_ || !plan_->reference) return FollowRefState::kProxFar;
  const double radius = std::isfinite(plan_->reference->radius) ? std::max(0.0f, plan_->reference->radius) : 0.0;
  if (horizontal_distance_m() <= kXyNearM + radius) prox |= FollowRefState::kProxXyNear;
  if (!plan_->depth_m || std::abs(depth_now() - *plan_->depth_m) <= kZNearM) prox |= FollowRefState::kProxZNear;
  return prox == 0 ? FollowRefState::kProxFar : prox;
}

std::uint8_t ImcVehicle::follow_state() const {
  if (!plan_ || !plan_->reference) return FollowRefState::kStateWait;
  const std::uint8_t prox = proximity();
  const bool xy = prox & FollowRefState::kProxXyNear;
  const bool z = prox & FollowRefState::kProxZNear;
  if (plan_->depth_m && *plan_->depth_m == 0.0) {
    return depth_now() <= kZNearM ? FollowRefState::kStateHover : FollowRefState::kStateElevator;
  }
  if (!xy) return FollowRefState::kStateGoto;
  if (!z) return FollowRefState::kStateElevator;
  // LOITER once arrived (the guidance reached the point, or the motors are
  // stopped), as DUNE loiters only after it arrives.
  return plan_->holding ? FollowRefState::kStateLoiter : FollowRefState::kStateGoto;
}

FollowRefState ImcVehicle::follow_ref_state(std::uint8_t state) const {
  FollowRefState s;
  if (plan_) {
    s.control_src = plan_->control_src;
    s.control_ent = plan_->control_ent;
    s.reference = plan_->reference;
  }
  s.state = state;
  s.proximity = state == FollowRefState::kStateWait ? FollowRefState::kProxFar : proximity();
  return s;
}

}  // namespace strata::vehicle
