#include "tactical/tactical_level.h"

#include <cassert>
#include <charconv>
#include <cmath>

#include <fmt/format.h>

#include "tactical/render.h"
#include "tactical/vehicle_link.h"

namespace strata::tactical {

std::optional<protocol::Verb> wire_verb(core::CallVerb verb) {
  switch (verb) {
    case core::CallVerb::Exec: return protocol::Verb::Exec;
    case core::CallVerb::Ask: return protocol::Verb::Ask;
    case core::CallVerb::Ood: return protocol::Verb::Ood;
    case core::CallVerb::Report: return std::nullopt;
  }
  return std::nullopt;
}

protocol::Request to_request(const RenderedCall& call) {
  assert(call.to_vehicle());
  protocol::Request r;
  r.verb = *wire_verb(call.verb);
  r.name = call.name;
  for (const auto& v : call.args) {
    if (v.type == Value::Type::String) {
      r.args.push_back(protocol::Value::string(v.text));
    } else if (std::nearbyint(v.number) == v.number && std::fabs(v.number) < 9.0e15) {
      // Whole numbers go as integers, so sleep(1) and sleep(1.0) send one line.
      r.args.push_back(protocol::Value::integer(static_cast<std::int64_t>(v.number)));
    } else {
      r.args.push_back(protocol::Value::real(v.number));
    }
  }
  return r;
}

namespace {

// The telemetry's fields in the log's names, to the microsecond like every
// logged number, each through put(key, value).
template <typename Put>
void each_telemetry_field(const protocol::Telemetry& t, Put&& put) {
  auto opt = [&](const char* key, const std::optional<double>& v) {
    if (v) put(key, log_time(*v));
  };
  opt("depth_m", t.depth_m);
  opt("filtered_depth_m", t.filtered_depth_m);
  opt("rate_mps", t.rate_mps);
  opt("thrust_n", t.thrust_n);
  opt("setpoint_m", t.setpoint_m);
  opt("heading_deg", t.heading_deg);
  for (auto [wire, logged] :
       {std::pair{"x", "x_m"}, std::pair{"y", "y_m"}, std::pair{"true_x", "true_x_m"}, std::pair{"true_y", "true_y_m"},
        std::pair{"pos_sd", "position_sd_m"}, std::pair{"speed", "speed_mps"}, std::pair{"alt", "altitude_m"}}) {
    const auto it = t.extras.find(wire);
    if (it == t.extras.end()) continue;
    double v = 0.0;
    const char* end = it->second.data() + it->second.size();
    const auto [ptr, ec] = std::from_chars(it->second.data(), end, v);
    if (ec == std::errc{} && ptr == end && std::isfinite(v)) put(logged, log_time(v));
  }
}

}  // namespace

nlohmann::ordered_json telemetry_log_fields(const protocol::Telemetry& t) {
  nlohmann::ordered_json fields;
  each_telemetry_field(t, [&fields](const char* key, double v) { fields[key] = v; });
  return fields;
}

LogLine telemetry_log_line(const protocol::Telemetry& t) {
  LogLine line("telemetry");
  line.add("sim_time", log_time(t.sim_time_s));
  each_telemetry_field(t, [&line](const char* key, double v) { line.add(key, v); });
  return line;
}

TacticalLevel::TacticalLevel(asio::io_context& io, const Catalogue& catalogue, std::shared_ptr<ExecutionLink> link,
                             DataCursor* cursor, MissionLog* log)
    : io_(io), catalogue_(catalogue), link_(std::move(link)), cursor_(cursor), log_(log) {
  if (!link_) return;
  link_->on_telemetry([this](const protocol::Telemetry& t) {
    sim_time_s_ = std::max(sim_time_s_, t.sim_time_s);
    last_heard_s_ = std::max(last_heard_s_, t.sim_time_s);
    if (log_) {
      log_->write(telemetry_log_line(t));
    }
    if (on_telemetry_) on_telemetry_(t);
  });
  link_->on_event([this](const protocol::Event& e) {
    sim_time_s_ = std::max(sim_time_s_, e.sim_time_s);
    last_heard_s_ = std::max(last_heard_s_, e.sim_time_s);
    ++events_heard_;
    last_event_ = e.text;
    if (log_) log_->event("vehicle_event", {{"text", e.text}, {"sim_time", e.sim_time_s}});
    if (on_event_) on_event_(e);
  });
  link_->on_garbage([this](const std::string& what) {
    if (log_) log_->error(fmt::format("from the vehicle: {}", what), sim_time_s_);
  });
}

void TacticalLevel::finish(const CallRecord& record, CallHandler& done, CallResult outcome) {
  --in_flight_;
  if (on_call_) {
    CallRecord r = record;
    r.sim_time_s = sim_time_s_;
    on_call_(r);
  }
  done(std::move(outcome));
}

void TacticalLevel::call(std::string_view name, std::vector<Value> args, CallHandler done, std::string_view guard) {
  ++calls_;
  ++in_flight_;
  CallRecord record;
  record.primitive = std::string(name);
  record.guard = std::string(guard);
  // Every outcome is delivered from the event loop, never inside call().
  // The link must not tell a lockstep vehicle to advance while an outcome is
  // queued here: the caller may answer it with more calls for this instant.
  auto hold = [this] { return link_ ? link_->hold() : ExecutionLink::Hold(); };
  auto fail_later = [this, &hold](CallRecord rec, CallHandler h, CallError e) {
    rec.error = e;
    if (log_) log_->error(fmt::format("{}: {}", rec.primitive, e.message), sim_time_s_);
    asio::post(io_, [this, rec = std::move(rec), h = std::move(h), e = std::move(e), held = hold()]() mutable {
      finish(rec, h, e);
      held.release();
    });
  };

  auto bad_call = [](std::string message) {
    return CallError{CallError::Kind::BadCall, std::nullopt, std::move(message)};
  };
  const Primitive* p = catalogue_.find(name);
  if (!p) {
    fail_later(record, std::move(done), bad_call(fmt::format("unknown primitive '{}'", name)));
    return;
  }
  record.verb = p->kind;
  core::Result<RenderedCall> rendered =
      p->data != DataSource::None
          ? (cursor_ ? advance_and_render(*p, args, *cursor_)
                     : core::Result<RenderedCall>(
                           core::make_error(core::ErrorCode::InvalidInput,
                                            fmt::format("'{}' needs mission data, and the mission names none", name))))
          : render(*p, args, cursor_);
  if (!rendered) {
    fail_later(record, std::move(done), bad_call(rendered.error().message));
    return;
  }
  const RenderedCall& rc = rendered.value();
  record.message = rc.text();

  if (!rc.to_vehicle()) {  // REPORT
    std::string text = rc.args.empty() ? std::string() : rc.args.front().text;
    if (log_) log_->report(text, sim_time_s_);
    if (on_report_) on_report_(text, sim_time_s_);
    record.value = true;
    asio::post(io_, [this, record, done = std::move(done), t = sim_time_s_, held = hold()]() mutable {
      finish(record, done, CallOutcome{true, t});
      held.release();
    });
    return;
  }
  if (!link_) {
    fail_later(record, std::move(done), CallError{CallError::Kind::LinkLost, std::nullopt, "no vehicle link"});
    return;
  }
  protocol::Request request = to_request(rc);
  const std::string what = describe(request);
  auto timeout = std::chrono::milliseconds(static_cast<std::int64_t>(std::ceil(rc.timeout_s * wall_per_sim_ * 1000.0)));
  // The catalogue's timeout is in simulated seconds: in lockstep the link
  // holds the call to it in simulated time; on the wall clock it is scaled by
  // the speed. The link's own (wall) timeout is the floor: in lockstep it is
  // what catches a vehicle that answers nothing at all.
  auto id = std::make_shared<std::uint64_t>(0);
  *id = link_->send(
      std::move(request),
      [this, record, done = std::move(done), id, what,
       events_before = events_heard_](core::Result<protocol::VehicleMessage> reply) mutable {
        auto fail = [&](CallError e, const std::string& logged) {
          record.error = CallError{e.kind, e.vehicle_code, logged};
          if (log_) log_->reply(*id, {{"error", logged}}, sim_time_s_);
          finish(record, done, std::move(e));
        };
        if (!reply) {
          // A simulated-time timeout ends the call at the vehicle's time, later than its last reply.
          if (auto t = link_->sim_time_s(); t && *t > sim_time_s_) sim_time_s_ = *t;
          fail(call_error_from_link(reply.error()), reply.error().message);
          return;
        }
        CallOutcome out;
        if (auto* d = std::get_if<protocol::Done>(&reply.value())) {
          out = {d->success, d->sim_time_s};
        } else if (auto* a = std::get_if<protocol::Answer>(&reply.value())) {
          out = {a->value, a->sim_time_s};
        } else if (auto* err = std::get_if<protocol::Err>(&reply.value())) {
          std::string text = refusal_text(what, *err);
          fail(CallError{CallError::Kind::Refused, err->code, text}, text);
          return;
        } else {
          fail(CallError{CallError::Kind::BadReply, std::nullopt,
                         fmt::format("unexpected reply to `{}`", record.message)},
               "unexpected reply");
          return;
        }
        sim_time_s_ = std::max(sim_time_s_, out.sim_time_s);
        last_heard_s_ = std::max(last_heard_s_, out.sim_time_s);
        record.value = out.value;
        if (!out.value && record.verb != core::CallVerb::Ask && events_heard_ > events_before) {
          record.vehicle_said = last_event_;
        }
        if (log_) log_->reply(*id, out.value ? 1 : 0, out.sim_time_s);
        finish(record, done, out);
      },
      std::max(timeout, link_->default_timeout()), rc.timeout_s);
  if (log_) log_->request(*id, record.primitive, record.message, sim_time_s_);
}

}  // namespace strata::tactical
