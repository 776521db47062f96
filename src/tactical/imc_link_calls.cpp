// tactical::ImcLink's calls: the address it is given, what it counted, and
// each exec/ask/ood it takes, carries out and answers (imc_link.h).
#include <charconv>
#include <cmath>

#include <fmt/format.h>

#include "protocol/rows.h"
#include "tactical/execution_level.h"
#include "tactical/imc_link.h"
#include "tactical/imc_link_internal.h"

namespace strata::tactical {

using core::ErrorCode;
using core::make_error;
using namespace imc_link_detail;

core::Result<ImcLinkOptions> parse_imc_vehicle(std::string_view text) {
  constexpr std::string_view kScheme = "imc://";
  auto bad = [&](std::string_view why) {
    return make_error(ErrorCode::InvalidInput,
                      fmt::format("'{}': {} (expected imc://HOST:PORT or imc://HOST:PORT/ID)", text, why));
  };
  if (execution_level_of(text) != ExecutionLevel::Imc) return bad("not an imc:// address");
  std::string_view rest = text.substr(kScheme.size());
  ImcLinkOptions o;
  if (auto slash = rest.find('/'); slash != std::string_view::npos) {
    std::string_view id = rest.substr(slash + 1);
    rest = rest.substr(0, slash);
    int base = 10;
    if (id.starts_with("0x") || id.starts_with("0X")) {
      id.remove_prefix(2);
      base = 16;
    }
    unsigned value = 0;
    auto [end, ec] = std::from_chars(id.data(), id.data() + id.size(), value, base);
    if (id.empty() || ec != std::errc{} || end != id.data() + id.size() || value == 0 || value >= imc::kAnyVehicle) {
      return bad("the vehicle's IMC id must be a number from 1 to 0xFFEF");
    }
    o.vehicle_id = static_cast<std::uint16_t>(value);
  }
  const auto colon = rest.rfind(':');
  if (colon == std::string_view::npos || colon == 0) return bad("no HOST:PORT");
  o.host = std::string(rest.substr(0, colon));
  std::string_view port = rest.substr(colon + 1);
  unsigned value = 0;
  auto [end, ec] = std::from_chars(port.data(), port.data() + port.size(), value);
  if (port.empty() || ec != std::errc{} || end != port.data() + port.size() || value == 0 || value > 65535) {
    return bad("the port must be a number from 1 to 65535");
  }
  o.port = static_cast<std::uint16_t>(value);
  return o;
}

std::string imc_summary(const ImcCounts& c) {
  std::string out = fmt::format("{} received, {} used, {} filtered, {} from others, {} dropped", c.received, c.used,
                                c.filtered, c.other_sources, c.dropped.total());
  if (c.dropped.total() > 0) out += fmt::format(" ({})", c.dropped.summary());
  return out;
}

nlohmann::ordered_json imc_counts_json(const ImcCounts& c) {
  nlohmann::ordered_json dropped = nlohmann::ordered_json::object();
  for (std::size_t i = 0; i < c.dropped.by_reason.size(); ++i) {
    if (c.dropped.by_reason[i] > 0)
      dropped[std::string(imc::drop_name(static_cast<imc::Drop>(i)))] = c.dropped.by_reason[i];
  }
  return {{"received", c.received},
          {"used", c.used},
          {"filtered", c.filtered},
          {"other_sources", c.other_sources},
          {"dropped", dropped}};
}

protocol::RequestId ImcLink::send(protocol::Request request, ReplyHandler handler,
                                  std::optional<std::chrono::milliseconds> /*timeout*/,
                                  std::optional<double> sim_timeout_s) {
  request.id = next_id_++;
  const protocol::RequestId id = request.id;
  auto later = [this](ReplyHandler h, core::Result<protocol::VehicleMessage> r) {
    asio::post(io_, [h = std::move(h), r = std::move(r)]() mutable { h(std::move(r)); });
  };
  // Lockstep: a call is activity, checked after its reply posted below.
  struct Noted {
    ImcLink& link;
    ~Noted() { link.note_activity(); }
  } noted{*this};
  if (!connected_) {
    later(std::move(handler),
          make_error(ErrorCode::Closed, fmt::format("cannot send `{} {}`: no link to the IMC vehicle",
                                                    protocol::verb_name(request.verb), request.name)));
    return id;
  }
  if (request.verb == protocol::Verb::Telemetry) {
    telemetry_hz_ = request.rate_hz;
    next_telemetry_s_ = state_.t_s;
    later(std::move(handler), protocol::VehicleMessage(protocol::Ok{id, state_.t_s}));
    return id;
  }
  if (request.verb != protocol::Verb::Exec && request.verb != protocol::Verb::Ask &&
      request.verb != protocol::Verb::Ood && request.verb != protocol::Verb::Ping) {
    later(std::move(handler), make_error(ErrorCode::InvalidInput, fmt::format("an IMC vehicle takes no `{}`",
                                                                              protocol::verb_name(request.verb))));
    return id;
  }
  Pending p;
  p.request = std::move(request);
  p.handler = std::move(handler);
  p.sent_s = state_.t_s;
  if (sim_timeout_s && std::isfinite(*sim_timeout_s) && *sim_timeout_s > 0)
    p.sim_deadline_s = state_.t_s + *sim_timeout_s;
  if (auto refusal = row_refusal(p.request)) {
    // As the Phoenix answers it (`err ID failed`): the mission's mistake.
    later(std::move(p.handler), protocol::VehicleMessage(protocol::Err{id, protocol::ErrorCode::Failed, *refusal}));
    return id;
  }
  if (p.request.verb != protocol::Verb::Ping) {
    if (auto taken = take(p); !taken) {
      later(std::move(p.handler), taken.error());
      return id;
    }
  }
  pending_.emplace(id, std::move(p));
  return id;
}

std::optional<std::string> ImcLink::row_refusal(const protocol::Request& r) const {
  if (r.verb != protocol::Verb::Exec || r.name != "next_row") return std::nullopt;
  if (!rows_) return std::string("next_row: no row pattern (start_rows first)");
  if (next_row_ >= rows_->count) return fmt::format("next_row: no row left (all {} rows started)", rows_->count);
  return std::nullopt;
}

core::Result<void> ImcLink::take(Pending& p) {
  const protocol::Request& r = p.request;
  const std::string_view f = name_of(r);
  if (!imc_mapping(r.verb, f)) {
    return make_error(ErrorCode::InvalidInput, fmt::format("an IMC vehicle has no '{}' (docs/imc.md)", f));
  }
  auto arg = [&](std::size_t i) -> core::Result<double> {
    auto v = number_arg(r, i);
    if (!v || !std::isfinite(*v)) {
      return make_error(ErrorCode::InvalidInput, fmt::format("`{}` needs a number as argument {}", f, i + 1));
    }
    return *v;
  };
  p.value = true;
  if (r.verb == protocol::Verb::Ask) {
    p.value.reset();  // answered from the state at the reply
    return {};
  }
  bool steer = false;
  if (f == "setpoint") {
    auto d = arg(0);
    auto t = arg(1);
    if (!d) return d.error();
    if (!t) return t.error();
    setpoint_depth_m_ = d.value();
    setpoint_timeout_s_ = t.value();
  } else if (f == "start_depth_filter") {
    filter_on_ = true;  // an IMC vehicle's navigation filters depth all the time
  } else if (f == "start_timer") {
    timer_end_s_ = state_.t_s + setpoint_timeout_s_;
  } else if (f == "set_timer") {
    auto s = arg(0);
    if (!s) return s.error();
    if (s.value() > 0) {
      timer_end_s_ = state_.t_s + s.value();
    } else {
      p.value = false;
      if (on_event_) on_event_(protocol::Event{state_.t_s, "exec set_timer failed: the limit must be positive"});
    }
  } else if (f == "start_rows") {
    double v[6];
    for (std::size_t i = 0; i < 6; ++i) {
      auto a = arg(i);
      if (!a) return a.error();
      v[i] = a.value();
    }
    std::string why;
    if (auto pattern = protocol::make_row_pattern(v[0], v[1], v[2], v[3], v[4], v[5], &why)) {
      rows_ = *pattern;
      next_row_ = 0;
    } else {
      p.value = false;
      if (on_event_) on_event_(protocol::Event{state_.t_s, "exec start_rows failed: " + why});
    }
  } else if (f == "sleep") {
    auto s = arg(0);
    if (!s) return s.error();
    p.wait = Wait::Until;
    p.until_s = state_.t_s + s.value();
  } else if (f == "set_altitude_floor") {
    auto a = arg(0);
    if (!a) return a.error();
    altitude_floor_m_ = a.value();
  } else if (f == "submerge") {
    if (!setpoint_depth_m_) {
      p.value = false;
      if (on_event_) on_event_(protocol::Event{state_.t_s, "exec submerge failed: no depth setpoint"});
    } else {
      desired_.z_m = *setpoint_depth_m_;
      steer = true;
    }
  } else if (f == "goto_depth") {
    auto d = arg(0);
    if (!d) return d.error();
    desired_.z_m = d.value();
    steer = true;
  } else if (f == "surface") {
    desired_.z_m = 0.0;
    if (replaced_) {
      // Another controller has the vehicle: taking it back, or aborting its
      // plan, is that controller's operator's call, not this run's.
      p.value = false;
      if (on_event_) {
        on_event_(protocol::Event{state_.t_s, "exec surface failed: another controller has the vehicle"});
      }
    } else if (state_.op_mode != imc::VehicleState::kOpModeError) {
      surface_method_ = "reference";
      steer = true;
      if (!plan_running_ && !plan_requested_) start_plan();  // timed out or failed: a new plan, to surface
    } else {
      // A vehicle in ERROR (or whose plan failed) takes no Reference: Abort
      // is the one command it still obeys.
      surface_method_ = "abort";
      send_abort();
      if (on_event_) {
        on_event_(protocol::Event{state_.t_s, "surface: the vehicle takes no Reference now; Abort sent"});
      }
    }
  } else if (f == "set_speed") {
    auto v = arg(0);
    if (!v) return v.error();
    // The cruise speed, as on the Phoenix: a goal held now takes it at once;
    // with none it waits for the next one.
    desired_.speed_mps = v.value();
    steer = waypoint_.has_value() || heading_deg_.has_value();
  } else if (f == "heading") {
    auto d = arg(0);
    if (!d) return d.error();
    heading_deg_ = wrap_deg(d.value());
    waypoint_.reset();
    const double h = *heading_deg_ / kRadToDeg;
    desired_.x_m = state_.x_m + options_.heading_lead_m * std::sin(h);
    desired_.y_m = state_.y_m + options_.heading_lead_m * std::cos(h);
    steer = true;
  } else if (f == "goto_xy" || f == "track" || f == "next_row") {
    double x = 0, y = 0;
    if (f == "next_row") {  // row_refusal() made sure there is one
      const protocol::Row row = protocol::row_of(*rows_, next_row_++);
      x = row.x1_m;  // as a track line: straight to its end (docs/imc.md)
      y = row.y1_m;
    } else {
      const std::size_t first = f == "track" ? 2 : 0;  // a track line: straight to its end (docs/imc.md)
      auto ax = arg(first);
      auto ay = arg(first + 1);
      if (!ax) return ax.error();
      if (!ay) return ay.error();
      x = ax.value();
      y = ay.value();
    }
    waypoint_ = {x, y};
    heading_deg_.reset();
    desired_.x_m = x;
    desired_.y_m = y;
    steer = true;
  } else if (f == "hold_position") {
    // The vehicle holds a Reference's point once there (DUNE loiters about
    // it): the point is where it is now.
    waypoint_ = {state_.x_m, state_.y_m};
    heading_deg_.reset();
    desired_.x_m = state_.x_m;
    desired_.y_m = state_.y_m;
    steer = true;
  } else if (f == "stop") {
    // Stopped (speed 0 at the current position); the cruise speed is kept
    // for the next goal, as on the Phoenix.
    waypoint_.reset();
    heading_deg_.reset();
    desired_.x_m = state_.x_m;
    desired_.y_m = state_.y_m;
    steer = true;
  } else if (f == "gps_fix") {
    p.value.reset();  // decided by the next GpsFix
    p.wait = Wait::NextGps;
    p.until_s = state_.t_s + options_.gps_wait_s;
  } else if (f == "start_sonar" || f == "stop_sonar") {
    send_payload(f == "start_sonar");
  } else if (f == "start_network") {
    p.value = plan_running_;
  } else if (f == "shutdown_network") {
    if (plan_running_) {
      mandone_sent_ = true;
      send_reference(/*mandone=*/true);
      p.wait = Wait::PlanEnd;
    }
  }
  if (steer) {
    state_.ref_state.reset();
    state_.proximity.reset();
    if (plan_running_) {
      send_reference();
    } else if (!plan_requested_) {
      // No plan takes it: the vehicle does nothing, so the call says 0.
      p.value = false;
      if (on_event_) {
        on_event_(
            protocol::Event{state_.t_s, fmt::format("exec {} failed: no plan of this run executes on the vehicle", f)});
      }
    }
  }
  return {};
}

bool ImcLink::ask(std::string_view q) const {
  const auto& s = state_;
  const bool z_near = s.proximity && (*s.proximity & imc::FollowRefState::kProxZNear) != 0;
  const bool xy_near = s.proximity && (*s.proximity & imc::FollowRefState::kProxXyNear) != 0;
  if (q == "depth_filter_off") return !filter_on_;
  if (q == "time_out") return timer_end_s_ && s.t_s + 1e-9 >= *timer_end_s_;
  if (q == "system_problem") return s.op_mode == imc::VehicleState::kOpModeError || s.error_count > 0;
  if (q == "surface_reached") return s.depth_m <= options_.surface_depth_m;
  if (q == "depth_reached") {
    // DUNE's Z_NEAR is within 1 m: the Phoenix's tolerance and settling on top.
    return desired_.z_m && z_near && std::fabs(s.depth_m - *desired_.z_m) < options_.depth_tolerance_m &&
           std::fabs(s.vz_mps) < options_.settle_rate_mps;
  }
  if (q == "heading_reached") {
    if (!heading_deg_) return false;
    double err = std::fabs(wrap_deg(s.psi_deg - *heading_deg_));
    err = std::min(err, 360.0 - err);
    return err < options_.heading_tolerance_deg && std::fabs(s.r_dps) < options_.heading_settle_dps;
  }
  if (q == "waypoint_reached") return waypoint_ && xy_near;
  if (q == "rows_done") return rows_ && next_row_ >= rows_->count;
  if (q == "gps_available") {
    // The newest GpsFix valid and fresh, at the surface: what gps_fix would take.
    return s.gps_valid && s.gps_at_s && s.t_s - *s.gps_at_s <= options_.gps_wait_s &&
           s.depth_m <= options_.surface_depth_m;
  }
  if (q == "position_uncertain") return s.position_sd_m && *s.position_sd_m > options_.position_limit_m;
  if (q == "altitude_low") {
    const bool dead = s.alt_m < 0 && s.depth_m > options_.surface_depth_m;
    return dead || (s.alt_m >= 0 && s.alt_m < altitude_floor_m_);
  }
  return false;
}

bool ImcLink::ready(const Pending& p) const {
  switch (p.wait) {
    case Wait::NextState: return state_.t_s > p.sent_s;
    case Wait::Until: return state_.t_s + 1e-9 >= p.until_s;
    case Wait::PlanEnd: return !plan_running_;
    case Wait::NextGps:  // a fix after the call, or none in time: answered 0
      return (state_.gps_at_s && *state_.gps_at_s > p.sent_s) || state_.t_s + 1e-9 >= p.until_s;
  }
  return false;
}

void ImcLink::service_pending() {
  std::vector<protocol::RequestId> due;
  for (auto& [id, p] : pending_) {  // in id order
    const bool late = p.sim_deadline_s && state_.t_s + 1e-9 >= *p.sim_deadline_s;
    if (ready(p) || late) due.push_back(id);
  }
  for (protocol::RequestId id : due) {
    auto it = pending_.find(id);
    if (it == pending_.end()) continue;
    Pending p = std::move(it->second);
    pending_.erase(it);
    answer(id, p);
  }
}

void ImcLink::answer(protocol::RequestId id, Pending& p) {
  const protocol::Request& r = p.request;
  if (!ready(p)) {
    p.handler(
        make_error(ErrorCode::Timeout, fmt::format("no reply to `{} {}` within {} s of the vehicle's time",
                                                   protocol::verb_name(r.verb), r.name, *p.sim_deadline_s - p.sent_s)));
    return;
  }
  if (r.verb == protocol::Verb::Ping) {
    p.handler(protocol::VehicleMessage(protocol::Pong{id, state_.t_s}));
  } else if (r.verb == protocol::Verb::Ask) {
    p.handler(protocol::VehicleMessage(protocol::Answer{id, ask(r.name), state_.t_s}));
  } else {
    bool value = p.value.value_or(false);
    if (r.name == "gps_fix") {
      const bool heard = state_.gps_at_s && *state_.gps_at_s > p.sent_s;
      value = heard && state_.gps_valid && state_.depth_m <= options_.surface_depth_m;
      if (!value && on_event_) {
        on_event_(protocol::Event{state_.t_s, heard ? "exec gps_fix failed: the vehicle's GpsFix is not valid"
                                                    : "exec gps_fix failed: no GpsFix from the vehicle"});
      }
    }
    p.handler(protocol::VehicleMessage(protocol::Done{id, value, state_.t_s}));
  }
}

}  // namespace strata::tactical
