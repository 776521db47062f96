// The server's pacer: how simulated time moves (docs in server.h, "Clocks"):
// lockstep advances, the wall clock's tick, the sleeps that wait for their
// time, and what each step produces (events, pings, telemetry samples).
#include <algorithm>

#include <fmt/format.h>

#include "protocol/codec.h"
#include "vehicle/cycle_timer.h"
#include "vehicle/execution.h"
#include "vehicle/server.h"
#include "vehicle/wire_time.h"

namespace strata::vehicle {

using protocol::ErrorCode;

// Lockstep: steps every waiting request together until one is due, answers
// all that are due, then the advance itself. With nothing waiting, time does
// not move, unless the advance names a time (until_s): then it moves to that
// time, and never past it, even with requests waiting (their replies come
// with a later advance). A bounded advance is answered with the time.
void VehicleServer::advance(std::optional<protocol::RequestId> advance_id, std::optional<double> until_s) {
  std::optional<double> until;
  if (until_s) until = std::min(*until_s, sim_.time_s() + kMaxAdvanceSpanS);
  const auto may_step = [&] { return !until || sim_.time_s() + 1e-9 < *until; };
  if (!waiting_.empty()) {
    std::uint64_t next_due = waiting_.front().due_cycle;
    for (const auto& w : waiting_) next_due = std::min(next_due, w.due_cycle);
    while (sim_.cycle() < next_due && !sim_.link_lost() && may_step()) step_one();
  } else if (until) {
    while (!sim_.link_lost() && may_step()) step_one();
  }
  if (sim_.link_lost()) {
    // The replies would be lost with the link.
    waiting_.clear();
    if (!until) {
      // Nobody can ask the simulation to move now: it runs on alone, and the
      // watchdog trips after watchdog_s of silence (run_alone trips it in
      // simulated time).
      cancel_silence_watchdog();
      if (!running_alone_) run_alone(sim_.time_s() + sim_.params().watchdog_s);
      return;
    }
    // The clock is the simulator's, not the link's: time moves on to the
    // client's bound, and the watchdog trips on the way (watch_lost_link).
    while (may_step()) step_one();
  } else {
    reply_due();
  }
  if (advance_id) {
    if (until) {
      send_clock(protocol::Ok{*advance_id, wire_time(sim_.time_s())});
    } else {
      send(protocol::Ok{*advance_id, std::nullopt});
    }
  }
  arm_silence_watchdog();  // silence counts from the reply, not from the request
}

void VehicleServer::reply_due() {
  std::vector<Waiting> due;
  std::erase_if(waiting_, [&](const Waiting& w) {
    if (w.due_cycle > sim_.cycle()) return false;
    due.push_back(w);
    return true;
  });
  std::sort(due.begin(), due.end(), [](const Waiting& a, const Waiting& b) { return a.request.id < b.request.id; });
  const double t = wire_time(sim_.time_s());
  for (const auto& w : due) {
    if (w.request.verb == protocol::Verb::Ask) {
      // The answer is the state after the cycle the question cost.
      send(protocol::Answer{w.request.id, execute(sim_, w.request).value, t});
    } else {
      send(protocol::Done{w.request.id, w.value, t});
    }
  }
}

void VehicleServer::step_one() {
  sim_.step();
  watch_lost_link();
  after_step();
}

void VehicleServer::watch_lost_link() {
  if (options_.clock != protocol::ClockMode::Lockstep) return;  // wall: tick() counts the silence
  if (!sim_.link_lost()) {
    silent_since_s_.reset();
    return;
  }
  if (!silent_since_s_) {
    silent_since_s_ = sim_.time_s();
    log(fmt::format("{:.1f} s: link lost (scenario)", sim_.time_s()));
  }
  if (!sim_.watchdog_tripped() && sim_.network_up() &&
      sim_.time_s() + 1e-9 >= *silent_since_s_ + sim_.params().watchdog_s) {
    sim_.watchdog_trip(fmt::format("link silent for {:.1f} s", sim_.params().watchdog_s));
    surfaced_in_silence_ = false;
  }
  // Nobody hears the telemetry now: the vehicle's log says when it is up.
  if (sim_.watchdog_tripped() && !surfaced_in_silence_ && sim_.surface_reached()) {
    surfaced_in_silence_ = true;
    log(fmt::format("{:.1f} s: at the surface (link silent); holding", sim_.time_s()));
  }
}

void VehicleServer::after_step() {
  flush_events();
  flush_pings();
  if (auto m = telemetry_.sample(sim_)) send(*m);
}

// Pings go to the sonar socket as soon as a step has made them; the sonar
// starting or stopping is told there and on the control link.
void VehicleServer::flush_pings() {
  auto pings = sim_.take_pings();
  if (!sonar_) return;
  const bool on = sim_.sonar_on();
  const bool changed = on != sonar_was_on_;
  sonar_was_on_ = on;
  if (changed && on) sonar_->status(sim_.time_s(), true);
  for (const auto& p : pings) sonar_->ping(p);
  if (changed) {
    if (!on) sonar_->status(sim_.time_s(), false);
    // The event reaches the mission log: no port in it (it is random, and a
    // run must log the same bytes every time; hello's reply carries it). The
    // operator's console is told where the pings go.
    const std::string text = on ? "sonar on" : "sonar off";
    log(on ? fmt::format("{:.1f} s: sonar on: pings on port {}", sim_.time_s(), sonar_->port())
           : fmt::format("{:.1f} s: sonar off", sim_.time_s()));
    send(protocol::Event{wire_time(sim_.time_s()), text});
  }
}

void VehicleServer::flush_events() {
  for (auto& ev : sim_.take_events()) {
    log(fmt::format("{:.1f} s: {}", ev.time_s, ev.text));
    send(protocol::Event{wire_time(ev.time_s), ev.text});
  }
}

void VehicleServer::reply_later(protocol::RequestId id, double until_s) { deferred_.push_back({id, until_s}); }

void VehicleServer::tick() {
  arm_next_cycle(tick_timer_, sim_.params().cycle_s, options_.speed);
  tick_timer_.async_wait([this](const asio::error_code& e) {
    if (e || stopped_) return;
    step_one();
    check_wall_settled();
    // Every sleep whose time has come, whatever was sent before it: a
    // `sleep 2` sent after a `sleep 5` must not wait for it. In id order.
    std::vector<Deferred> due;
    std::erase_if(deferred_, [&](const Deferred& d) {
      if (sim_.time_s() + 1e-9 < d.until_s) return false;
      due.push_back(d);
      return true;
    });
    std::sort(due.begin(), due.end(), [](const Deferred& a, const Deferred& b) { return a.id < b.id; });
    for (const auto& d : due) {
      send(protocol::Done{d.id, true, wire_time(sim_.time_s())});
      // As in lockstep, silence counts from the reply: a client waiting for
      // its `sleep 5` is not silent (unless the link is cut: nothing went).
      if (!sim_.link_lost()) last_rx_s_ = std::max(last_rx_s_, sim_.time_s());
    }
    if (sim_.time_s() + 1e-9 >= next_heartbeat_s_) {
      send(protocol::Heartbeat{wire_time(sim_.time_s())});
      next_heartbeat_s_ += 1.0;
    }
    const bool client_waits = !deferred_.empty() && !sim_.link_lost();
    if (controller_ && !controller_->closing() && !client_waits &&
        sim_.time_s() - last_rx_s_ >= sim_.params().watchdog_s) {
      trip(fmt::format("link silent for {:.1f} s", sim_.params().watchdog_s));
    }
    tick();
  });
}

}  // namespace strata::vehicle
