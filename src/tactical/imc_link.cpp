// tactical::ImcLink's session: connecting, what it hears from the vehicle
// (its clock, state, plan and faults), telemetry, and how it ends
// (imc_link.h). What it sends is imc_link_send.cpp; its calls,
// imc_link_calls.cpp.
#include "tactical/imc_link.h"

#include <charconv>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "tactical/execution_level.h"
#include "tactical/imc_link_internal.h"

namespace strata::tactical {

using core::ErrorCode;
using core::make_error;
using namespace imc_link_detail;

std::shared_ptr<ImcLink> ImcLink::create(asio::io_context& io, ImcLinkOptions options) {
  return std::shared_ptr<ImcLink>(new ImcLink(io, std::move(options)));
}

ImcLink::ImcLink(asio::io_context& io, ImcLinkOptions options)
    : io_(io),
      options_(std::move(options)),
      socket_(io),
      buffer_(65536),
      heartbeat_timer_(io),
      lost_timer_(io),
      connect_timer_(io) {}

ImcLink::~ImcLink() {
  // A link let go without close() (a run that failed after connecting) still
  // ends its plan: the vehicle is never left following a dead controller.
  if (plan_running_ && !closed_) {
    mandone_sent_ = true;
    send_reference(/*mandone=*/true);
  }
  asio::error_code ignored;
  socket_.close(ignored);
}

std::optional<double> ImcLink::sim_time_s() const {
  if (!state_.have_state) return std::nullopt;
  return state_.t_s;
}

void ImcLink::connect(std::function<void(core::Result<ImcVehicleInfo>)> done) {
  asio::error_code ec;
  asio::ip::udp::resolver resolver(io_);
  auto found = resolver.resolve(asio::ip::udp::v4(), options_.host, std::to_string(options_.port), ec);
  if (ec || found.empty()) {
    asio::post(io_, [done, host = options_.host, ec] {
      done(make_error(ErrorCode::Io, fmt::format("cannot resolve the IMC vehicle's host '{}': {}", host,
                                                 ec ? ec.message() : std::string("no address"))));
    });
    return;
  }
  vehicle_endpoint_ = *found.begin();
  if (options_.bind_address.empty()) {
    // The local address the kernel would send from: a connected UDP socket
    // asks the routing table, and sends nothing.
    asio::ip::udp::socket probe(io_);
    probe.open(asio::ip::udp::v4(), ec);
    if (!ec) probe.connect(vehicle_endpoint_, ec);
    options_.bind_address = ec ? std::string("127.0.0.1") : probe.local_endpoint(ec).address().to_string();
    ec.clear();
  }
  auto bind = asio::ip::make_address(options_.bind_address, ec);
  if (!ec) socket_.open(asio::ip::udp::v4(), ec);
  if (!ec) socket_.bind(asio::ip::udp::endpoint(bind, 0), ec);
  if (ec) {
    asio::post(io_, [done, ec, a = options_.bind_address] {
      done(make_error(ErrorCode::Io, fmt::format("cannot open a UDP socket on {}: {}", a, ec.message())));
    });
    return;
  }
  // A burst (a flood, or DUNE's 800 packets/s behind a slow loop) waits in
  // the kernel rather than pushing out the states that matter; the kernel
  // caps this at net.core.rmem_max.
  socket_.set_option(asio::socket_base::receive_buffer_size(4 << 20), ec);
  local_port_ = socket_.local_endpoint(ec).port();
  if (options_.plan_id.empty()) options_.plan_id = fmt::format("strata-{}", local_port_);
  if (options_.system_id == 0) options_.system_id = static_cast<std::uint16_t>(0x4000 | (local_port_ & 0x1FFF));
  connecting_ = std::move(done);
  if (options_.vehicle_id) {
    vehicle_.id = *options_.vehicle_id;
  }
  start_receive();
  announce();
  arm_heartbeat();
  auto me = self();
  connect_timer_.expires_after(options_.connect_timeout);
  connect_timer_.async_wait([this, me](const asio::error_code& e) {
    if (e || !connecting_) return;
    const std::string what = !vehicle_heard_ ? "no Announce from it"
                             : !t0_          ? "no EstimatedState from it"
                                             : "no answer to the plan's start (PlanControl)";
    auto waiting = std::move(connecting_);
    connecting_ = nullptr;
    close();
    waiting(make_error(ErrorCode::Timeout,
                       fmt::format("the IMC vehicle at {}:{} did not answer within {} ms: {}", options_.host,
                                   options_.port, options_.connect_timeout.count(), what)));
  });
}

void ImcLink::start_receive() {
  auto me = self();
  socket_.async_receive_from(asio::buffer(buffer_), sender_, [this, me](const asio::error_code& e, std::size_t n) {
    if (closed_ || e == asio::error::operation_aborted) return;
    if (!e) on_datagram(n);  // another error (an ICMP answer to a datagram) ends nothing
    start_receive();
  });
}

void ImcLink::on_datagram(std::size_t bytes) {
  ++counts_.received;
  const std::span<const std::uint8_t> datagram(buffer_.data(), bytes);
  // The vehicle is its address and, once known, its IMC id; a second
  // controller on the same vehicle writes from elsewhere.
  if (sender_ != vehicle_endpoint_) {
    ++counts_.other_sources;
    return;
  }
  auto header = imc::peek_header(datagram);
  if (!header) {
    counts_.dropped.add(bytes < imc::kHeaderBytes ? imc::Drop::Truncated : imc::Drop::BadSync);
    return;
  }
  if (!wanted(header->mgid)) {
    ++counts_.filtered;
    return;
  }
  if (vehicle_heard_ && header->src != vehicle_.id) {
    ++counts_.other_sources;
    return;
  }
  auto decoded = imc::decode(datagram);
  if (auto* drop = std::get_if<imc::Drop>(&decoded)) {
    counts_.dropped.add(*drop);
    // The log hears of the first of each reason and then every 1000th: a
    // flood must not write a line per datagram.
    const std::uint64_t n = counts_.dropped.by_reason[static_cast<std::size_t>(*drop)];
    if (on_garbage_ && (n == 1 || n % 1000 == 0)) {
      on_garbage_(fmt::format("IMC packets dropped: {} {} so far", n, imc::drop_name(*drop)));
    }
    return;
  }
  if (!std::isfinite(std::get<imc::Packet>(decoded).header.timestamp)) {
    counts_.dropped.add(imc::Drop::BadField);  // a time that is no time
    return;
  }
  ++counts_.used;
  handle(std::get<imc::Packet>(decoded));
}

void ImcLink::handle(const imc::Packet& packet) {
  if (options_.tap) options_.tap(false, imc::name_of(packet.header.mgid));
  const imc::Message& m = packet.message;
  if (const auto* a = std::get_if<imc::Announce>(&m)) {
    if (!vehicle_heard_ && (!options_.vehicle_id || packet.header.src == *options_.vehicle_id)) {
      vehicle_heard_ = true;
      vehicle_.id = packet.header.src;
      vehicle_.name = printable(a->sys_name);
      // One of the services, separated by ';' (IMC's Announce).
      for (std::string_view rest = a->services; !rest.empty();) {
        const auto cut = rest.find(';');
        lockstep_ = lockstep_ || rest.substr(0, cut) == imc::kLockstepService;
        rest = cut == std::string_view::npos ? std::string_view{} : rest.substr(cut + 1);
      }
    }
    return;
  }
  if (!vehicle_heard_) return;  // nothing counts before the vehicle said who it is
  if (std::holds_alternative<imc::Heartbeat>(m)) {
    // Lockstep: the vehicle's Heartbeat ends its cycle (its streams came
    // before it); the answer goes once what they started is done.
    if (lockstep_ && t0_) {
      cycle_end_s_ = run_time(packet.header.timestamp);
      note_activity();
    }
    return;
  }
  if (std::holds_alternative<imc::EstimatedState>(m)) {
    on_estimated_state(packet);
    return;
  }
  if (const auto* vs = std::get_if<imc::VehicleState>(&m)) {
    on_vehicle_state(*vs);
  } else if (const auto* g = std::get_if<imc::GpsFix>(&m)) {
    // A fix: every validity bit DUNE sets at the surface, and satellites.
    // A fix: a valid position from satellites (a receiver need not report
    // every validity bit DUNE's simulator sets).
    state_.gps_valid = (g->validity & imc::GpsFix::kValidPos) != 0 && g->satellites > 0;
    state_.gps_at_s = state_.t_s;  // answered at the next EstimatedState
  } else if (const auto* pc = std::get_if<imc::PlanControl>(&m)) {
    on_plan_control(*pc);
  } else if (const auto* pcs = std::get_if<imc::PlanControlState>(&m)) {
    on_plan_control_state(*pcs);
  } else if (const auto* frs = std::get_if<imc::FollowRefState>(&m)) {
    on_follow_ref_state(*frs);
  } else if (const auto* nu = std::get_if<imc::NavigationUncertainty>(&m)) {
    // The horizontal 1-sigma as the Phoenix defines it: sqrt(var_x + var_y).
    const double var = static_cast<double>(nu->x) + nu->y;
    if (std::isfinite(var) && var >= 0) state_.position_sd_m = std::sqrt(var);
  } else if (const auto* lb = std::get_if<imc::LogBookEntry>(&m)) {
    if (on_event_ && lb->type != imc::LogBookEntry::kTypeDebug && t0_) {
      on_event_(protocol::Event{state_.t_s, fmt::format("{}: {}", printable(lb->context), printable(lb->text))});
    }
  }
}

void ImcLink::on_estimated_state(const imc::Packet& packet) {
  const auto& es = std::get<imc::EstimatedState>(packet.message);
  observe_clock(packet.header.timestamp);
  state_.have_state = true;
  // The navigation origin of the first state is the run's frame; a vehicle
  // that moves its origin later has its positions carried into that frame.
  if (!origin_) origin_ = std::pair{es.lat, es.lon};
  state_.lat0 = origin_->first;
  state_.lon0 = origin_->second;
  const double north_shift = (es.lat - origin_->first) * kEarthRadiusM;
  const double east_shift = (es.lon - origin_->second) * kEarthRadiusM * std::cos(origin_->first);
  state_.x_m = es.y + east_shift;  // IMC x is north, y east; Strata's x is east, y north
  state_.y_m = es.x + north_shift;
  state_.depth_m = es.depth;
  state_.alt_m = es.alt;
  state_.vz_mps = es.vz;
  state_.psi_deg = wrap_deg(es.psi * kRadToDeg);
  state_.r_dps = es.r * kRadToDeg;
  state_.u_mps = es.u;
  arm_lost();
  if (!plan_requested_ && connecting_) start_plan();
  if (!connected_) return;
  if (state_.t_s - last_reference_s_ + 1e-9 >= options_.reference_period_s) send_reference(mandone_sent_);
  emit_telemetry();
  service_pending();
}

void ImcLink::observe_clock(double timestamp) {
  if (!t0_) {
    t0_ = timestamp;
    return;
  }
  const double t = run_time(timestamp);
  // A step (a vehicle that sets its clock from GPS at the surface, or one
  // timestamp far off): the run's clock goes on from where it was, never
  // back and never leaping a deadline.
  if (t < state_.t_s - kMaxClockStepS || t > state_.t_s + kMaxClockStepS) {
    if (on_event_) {
      on_event_(protocol::Event{state_.t_s, fmt::format("the vehicle's clock stepped by {:.1f} s; the run's clock goes "
                                                        "on from {:.1f} s",
                                                        t - state_.t_s, state_.t_s)});
    }
    *t0_ = timestamp - state_.t_s;
    return;
  }
  state_.t_s = std::max(state_.t_s, t);
}

void ImcLink::on_vehicle_state(const imc::VehicleState& m) {
  const bool was_error = state_.op_mode == imc::VehicleState::kOpModeError;
  state_.op_mode = m.op_mode;
  state_.error_count = m.error_count;
  state_.error_ents = m.error_ents;
  state_.last_error = m.last_error;
  const bool error = m.op_mode == imc::VehicleState::kOpModeError;
  if (error && !was_error && on_event_ && t0_) {
    on_event_(protocol::Event{state_.t_s, fmt::format("vehicle in ERROR: {}{}{}", printable(m.error_ents),
                                                      m.last_error.empty() ? "" : ": ", printable(m.last_error))});
  }
}

void ImcLink::on_plan_control(const imc::PlanControl& m) {
  if (m.plan_id != options_.plan_id) return;  // another controller's plan, or its replies
  if (m.type == imc::PlanControl::kSuccess && m.op == imc::PlanControl::kStop && plan_running_ && !mandone_sent_) {
    stopped_elsewhere_ = true;
    plan_running_ = false;
    plan_requested_ = false;
    fault(fmt::format("this run's plan '{}' was stopped by another controller (PlanControl STOP)", options_.plan_id));
    return;
  }
  if (m.type == imc::PlanControl::kSuccess) {
    if (mandone_sent_) {
      plan_ended();  // "plan completed": our MANDONE ended it
    } else if (plan_requested_ && !plan_running_ && m.request_id == plan_request_id_) {
      plan_started();
    }
    return;
  }
  if (m.type != imc::PlanControl::kFailure) return;
  if (connecting_ && m.request_id == plan_request_id_) {
    auto done = std::move(connecting_);
    connecting_ = nullptr;
    close();
    done(make_error(ErrorCode::Protocol, fmt::format("the IMC vehicle refused the plan: {}", printable(m.info))));
    return;
  }
  plan_requested_ = false;
  if (plan_running_) {
    if (on_event_) {
      on_event_(protocol::Event{state_.t_s, fmt::format("plan '{}' failed: {}", m.plan_id, printable(m.info))});
    }
    plan_ended();
  }
}

void ImcLink::plan_started() {
  plan_running_ = true;
  plan_confirmed_ = false;
  last_reference_s_ = -1e300;
  if (!desired_.x_m) {
    desired_.x_m = state_.x_m;  // hold where it is until told otherwise
    desired_.y_m = state_.y_m;
  }
  send_reference();
  if (!connecting_) return;
  connected_ = true;
  connect_timer_.cancel();
  auto done = std::move(connecting_);
  connecting_ = nullptr;
  done(vehicle_);
}

void ImcLink::plan_ended() {
  if (!plan_running_) return;
  plan_running_ = false;
  service_pending();  // a shutdown waiting for the plan's end has it
}

void ImcLink::on_plan_control_state(const imc::PlanControlState& m) {
  const bool executing = m.state == imc::PlanControlState::kStateExecuting;
  if (connecting_ && plan_requested_ && executing && m.plan_id == options_.plan_id) {
    plan_started();  // its PlanControl reply was lost on the way; the state says it runs
    return;
  }
  if (!plan_running_) return;
  if (m.plan_id == options_.plan_id) {
    if (executing) plan_confirmed_ = true;
    if (!executing && mandone_sent_) {
      plan_ended();
    } else if (!executing && plan_confirmed_ && !stopped_elsewhere_) {
      // Ours, no longer executing, and not because of us: stopped by an
      // operator or another controller (a failure of the vehicle's own comes
      // as a PlanControl FAILURE with its reason, before this).
      stopped_elsewhere_ = true;
      plan_running_ = false;
      plan_requested_ = false;
      fault(fmt::format("this run's plan '{}' was stopped outside the run (the vehicle says it is not executing)",
                        options_.plan_id));
    }
    return;
  }
  // Only once the vehicle said it runs ours: a state sent before our start
  // may still name the plan it replaced.
  if (executing && plan_confirmed_) {
    replaced_ = true;
    plan_running_ = false;
    fault(fmt::format("another controller replaced this run's plan '{}' with '{}'", options_.plan_id, m.plan_id));
  }
}

void ImcLink::on_follow_ref_state(const imc::FollowRefState& m) {
  if (m.control_src != options_.system_id || m.control_ent != options_.entity_id) return;
  if (m.state == imc::FollowRefState::kStateTimeout) {
    if (plan_running_) {
      plan_running_ = false;
      plan_requested_ = false;
      fault(fmt::format("the vehicle's FollowReference timed out (no Reference for {} s of its time)",
                        options_.follow_timeout_s));
    }
    return;
  }
  if (m.reference && our_reference(*m.reference)) {
    state_.ref_state = m.state;
    state_.proximity = m.proximity;
  }
}

bool ImcLink::our_reference(const imc::Reference& r) const {
  // The echo of the Reference this link last sent: FollowRefState answers
  // each Reference, and one in flight when the desired state changed
  // speaks of the old target.
  if (desired_.x_m && desired_.y_m) {
    auto [lat, lon] = lat_lon(*desired_.x_m, *desired_.y_m);
    if (std::fabs(r.lat - lat) > 1e-9 || std::fabs(r.lon - lon) > 1e-9) return false;
  }
  const bool z_flag = (r.flags & imc::Reference::kFlagZ) != 0;
  if (z_flag != desired_.z_m.has_value()) return false;
  if (desired_.z_m && (!r.z || std::fabs(r.z->value - *desired_.z_m) > 1e-3)) return false;
  return true;
}

void ImcLink::arm_lost() {
  auto me = self();
  lost_timer_.expires_after(options_.lost_after);
  lost_timer_.async_wait([this, me](const asio::error_code& e) {
    if (e || closed_ || !connected_) return;
    lost(fmt::format("no EstimatedState from the IMC vehicle for {} ms", options_.lost_after.count()));
  });
}

void ImcLink::emit_telemetry() {
  if (telemetry_hz_ <= 0 || !on_telemetry_ || state_.t_s + 1e-9 < next_telemetry_s_) return;
  next_telemetry_s_ = state_.t_s + 1.0 / telemetry_hz_;
  protocol::Telemetry t;
  t.sim_time_s = state_.t_s;
  t.depth_m = state_.depth_m;
  t.heading_deg = state_.psi_deg;
  t.rate_mps = state_.vz_mps;
  if (desired_.z_m) t.setpoint_m = *desired_.z_m;
  t.extras["x"] = fmt::format("{}", state_.x_m);
  t.extras["y"] = fmt::format("{}", state_.y_m);
  t.extras["speed"] = fmt::format("{}", state_.u_mps);
  if (state_.alt_m >= 0) t.extras["alt"] = fmt::format("{}", state_.alt_m);
  on_telemetry_(t);
}

void ImcLink::fault(const std::string& why) {
  if (faulted_) return;
  faulted_ = true;
  if (on_event_) on_event_(protocol::Event{state_.t_s, why});
  service_pending();
  if (on_fault_) on_fault_(why);
}

void ImcLink::lost(const std::string& why) {
  if (lost_) return;
  lost_ = true;
  connected_ = false;
  fail_all(make_error(ErrorCode::Closed, why));
  if (on_lost_) on_lost_(make_error(ErrorCode::Closed, why));
}

void ImcLink::fail_all(const core::Error& error) {
  auto pending = std::move(pending_);
  pending_.clear();
  for (auto& [id, p] : pending) {
    p.handler(make_error(error.code, fmt::format("`{} {}` (request {}) failed: {}", protocol::verb_name(p.request.verb),
                                                 p.request.name, id, error.message)));
  }
}

void ImcLink::close() {
  if (closed_) return;
  // A plan still running when the run lets go is ended, never left to time out.
  if (plan_running_ && connected_) {
    mandone_sent_ = true;
    send_reference(/*mandone=*/true);
  }
  plan_running_ = false;
  closed_ = true;
  connected_ = false;
  heartbeat_timer_.cancel();
  lost_timer_.cancel();
  connect_timer_.cancel();
  asio::error_code ignored;
  socket_.close(ignored);
  fail_all(make_error(ErrorCode::Closed, "the link was closed"));
}

}  // namespace strata::tactical
