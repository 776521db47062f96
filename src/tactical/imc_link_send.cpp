// tactical::ImcLink's side of the conversation: the plan it starts, the
// References that steer, the payload switch, every packet it sends, its
// Announce and Heartbeat, and its answer to a lockstep vehicle's cycles
// (imc_link.h). What it hears is imc_link.cpp; its calls, imc_link_calls.cpp.
#include <cmath>

#include <fmt/format.h>

#include "tactical/imc_link.h"
#include "tactical/imc_link_internal.h"

namespace strata::tactical {

using namespace imc_link_detail;

std::pair<double, double> ImcLink::lat_lon(double x_m, double y_m) const {
  const double lat = state_.lat0 + y_m / kEarthRadiusM;
  const double lon = state_.lon0 + x_m / (kEarthRadiusM * std::cos(state_.lat0));
  return {lat, lon};
}

void ImcLink::start_plan() {
  if (!options_.monitor_entities.empty()) {
    imc::MonitorEntityState monitor;
    monitor.command = imc::MonitorEntityState::kCommandEnable;
    monitor.entities = options_.monitor_entities;
    send_packet(imc::Message(std::move(monitor)), vehicle_.id);
  }
  plan_requested_ = true;
  mandone_sent_ = false;
  plan_confirmed_ = false;
  stopped_elsewhere_ = false;
  plan_request_id_ = next_request_id_++;
  imc::FollowReference follow;
  follow.control_src = options_.system_id;
  follow.control_ent = options_.entity_id;
  follow.timeout = static_cast<float>(options_.follow_timeout_s);
  follow.loiter_radius = 0;
  follow.altitude_interval = 0;
  imc::PlanManeuver maneuver;
  maneuver.maneuver_id = "follow";
  maneuver.data = imc::Inline(imc::Message(follow));
  imc::PlanSpecification spec;
  spec.plan_id = options_.plan_id;
  spec.description = "Strata: a mission steered step by step";
  spec.start_man_id = "follow";
  spec.maneuvers.push_back(std::move(maneuver));
  imc::PlanControl pc;
  pc.type = imc::PlanControl::kRequest;
  pc.op = imc::PlanControl::kStart;
  pc.request_id = plan_request_id_;
  pc.plan_id = options_.plan_id;
  pc.arg = imc::Inline(imc::Message(std::move(spec)));
  send_packet(imc::Message(std::move(pc)), vehicle_.id);
}

void ImcLink::send_reference(bool mandone) {
  imc::Reference r;
  r.flags = imc::Reference::kFlagLocation | imc::Reference::kFlagSpeed;
  // Always a location: a Reference without one reuses an older plan's
  // (measured on DUNE), so holding still means the current position.
  auto [lat, lon] = lat_lon(desired_.x_m.value_or(state_.x_m), desired_.y_m.value_or(state_.y_m));
  r.lat = lat;
  r.lon = lon;
  imc::DesiredSpeed speed;
  // As the Phoenix: toward a goal at cruise speed unless a speed was set.
  // Without a goal (stopped) the speed is 0; the cruise speed set is kept.
  speed.value = waypoint_ || heading_deg_ ? desired_.speed_mps.value_or(options_.cruise_speed_mps) : 0.0;
  speed.speed_units = imc::DesiredSpeed::kSpeedUnitsMetersPs;
  r.speed = speed;
  if (desired_.z_m) {
    r.flags |= imc::Reference::kFlagZ;
    imc::DesiredZ z;
    z.value = static_cast<float>(*desired_.z_m);
    z.z_units = imc::DesiredZ::kZUnitsDepth;
    r.z = z;
  }
  if (mandone) r.flags |= imc::Reference::kFlagManDone;
  last_reference_s_ = state_.t_s;
  send_packet(imc::Message(r), vehicle_.id);
}

void ImcLink::send_abort() { send_packet(imc::Message(imc::Abort{}), vehicle_.id); }

void ImcLink::send_payload(bool active) {
  imc::EntityParameter on;
  on.name = "Active";
  on.value = active ? "true" : "false";
  imc::SetEntityParameters set;
  set.name = options_.sonar_entity;
  set.params.push_back(std::move(on));
  send_packet(imc::Message(std::move(set)), vehicle_.id);
}

void ImcLink::send_packet(const imc::Message& message, std::uint16_t dst) {
  if (closed_ || !socket_.is_open()) return;
  imc::Packet packet;
  packet.header.timestamp = state_.have_state && t0_ ? *t0_ + state_.t_s : 0.0;
  packet.header.src = options_.system_id;
  packet.header.src_ent = options_.entity_id;
  packet.header.dst = dst;
  packet.header.dst_ent = imc::kAnyEntity;
  packet.message = message;
  auto bytes = imc::encode(packet);
  if (!bytes) {
    if (on_garbage_) on_garbage_(fmt::format("cannot encode an IMC message: {}", bytes.error().message));
    return;
  }
  if (options_.tap) options_.tap(true, imc::name_of(imc::id_of(message)));
  asio::error_code ec;  // UDP: a datagram lost is a datagram lost; the stream repeats itself
  socket_.send_to(asio::buffer(bytes.value()), vehicle_endpoint_, 0, ec);
  if (ec && on_garbage_ && ++send_errors_ % 1000 == 1) {
    on_garbage_(fmt::format("cannot send to the IMC vehicle: {} ({} so far)", ec.message(), send_errors_));
  }
}

void ImcLink::announce() {
  imc::Announce a;
  a.sys_name = options_.system_name;
  a.sys_type = imc::Announce::kSysTypeCcu;
  a.owner = imc::kNullId;
  a.services = fmt::format("imc+udp://{}:{}/", options_.bind_address, local_port_);
  send_packet(imc::Message(std::move(a)), imc::kNullId);
}

void ImcLink::arm_heartbeat() {
  auto me = self();
  heartbeat_timer_.expires_after(std::chrono::seconds(1));
  heartbeat_timer_.async_wait([this, me](const asio::error_code& e) {
    if (e || closed_) return;
    // DUNE forgets a peer after 30 s without traffic; Announce each 10 s as it does.
    // In lockstep a Heartbeat answers a cycle: the answers are the traffic.
    if (!lockstep_) send_packet(imc::Message(imc::Heartbeat{}), vehicle_heard_ ? vehicle_.id : imc::kNullId);
    // UDP: a plan start or its reply lost on the way is asked again.
    if (connecting_ && plan_requested_ && !plan_running_) start_plan();
    if (++heartbeats_ % 10 == 0 || !vehicle_heard_) announce();
    arm_heartbeat();
  });
}

void ImcLink::note_activity() {
  if (!lockstep_) return;
  const std::uint64_t generation = ++activity_;
  asio::post(io_, [weak = std::weak_ptr<ExecutionLink>(shared_from_this()), generation] {
    if (auto link = weak.lock()) std::static_pointer_cast<ImcLink>(link)->maybe_answer_cycle(generation);
  });
}

void ImcLink::maybe_answer_cycle(std::uint64_t generation) {
  if (generation != activity_ || closed_ || holds() > 0 || !cycle_end_s_) return;
  if (answered_s_ && *answered_s_ >= *cycle_end_s_) return;
  answered_s_ = cycle_end_s_;
  send_packet(imc::Message(imc::Heartbeat{}), vehicle_.id);  // stamped with the vehicle's newest time
  // The vehicle waited for this answer: its silence counts from now, not
  // from its last state (this side's work, however long, is not its loss).
  arm_lost();
}

}  // namespace strata::tactical
