// The server's watchdog (docs in server.h, "Watchdog" and "Hello"): the
// hello timeout, the silence timer, the controller's link dropping, the trip,
// and the lockstep vehicle running on alone until it is at the surface.
#include <algorithm>
#include <utility>

#include <fmt/format.h>

#include "protocol/codec.h"
#include "vehicle/server.h"
#include "vehicle/wire_time.h"

namespace strata::vehicle {

using protocol::ErrorCode;

// A client that connects and says nothing is closed after hello_timeout_s:
// it holds nothing meanwhile (a real controller's hello takes the vehicle),
// but is not kept for ever.
void VehicleServer::arm_hello_timeout(const std::shared_ptr<protocol::LineConnection>& c, asio::steady_timer& timer) {
  if (options_.hello_timeout_s <= 0) return;
  timer.expires_after(std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(std::min(options_.hello_timeout_s, 86400.0))));
  timer.async_wait([this, weak = std::weak_ptr<protocol::LineConnection>(c)](const asio::error_code& e) {
    auto conn = weak.lock();
    if (e || stopped_ || !conn || conn->closing() || !waiting_client(*conn)) return;
    const std::string why = fmt::format("no hello within {} s: closing this connection", options_.hello_timeout_s);
    log(fmt::format("{:.1f} s: {}", sim_.time_s(), why));
    write(*conn, protocol::encode(protocol::VehicleMessage{protocol::Err{0, ErrorCode::NotReady, why}}));
    conn->close_when_written(why);
    drop_waiting(*conn);
  });
}

void VehicleServer::arm_silence_watchdog() {
  if (options_.clock != protocol::ClockMode::Lockstep) return;  // wall: checked per tick
  const double limit_s = options_.lockstep_silence_s.value_or(sim_.params().watchdog_s);
  if (limit_s <= 0) return;                             // the controller is in this process: its end closes the link
  const double silence_s = std::min(limit_s, 86400.0);  // a day is "never" here
  silence_deadline_ =
      std::chrono::steady_clock::now() +
      std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(silence_s));
  if (!silence_waiting_) wait_for_silence();
}

void VehicleServer::wait_for_silence() {
  silence_waiting_ = true;
  silence_timer_.expires_at(silence_deadline_);
  silence_timer_.async_wait([this, generation = silence_generation_](const asio::error_code& e) {
    if (generation != silence_generation_) return;  // cancelled: a newer wait, or none, is in charge
    silence_waiting_ = false;
    if (e || stopped_ || !controller_ || controller_->closing() || !sim_.network_up()) return;
    // A line came since this wait began: the silence is shorter than it.
    if (std::chrono::steady_clock::now() < silence_deadline_) return wait_for_silence();
    trip(fmt::format("link silent for {:.1f} s", options_.lockstep_silence_s.value_or(sim_.params().watchdog_s)));
  });
}

void VehicleServer::cancel_silence_watchdog() {
  ++silence_generation_;
  silence_waiting_ = false;
  silence_timer_.cancel();
}

void VehicleServer::controller_gone() {
  if (!controller_) return;
  auto c = controller_;
  c->close("the controller is gone");
  on_closed(*c, protocol::CloseReason{protocol::CloseReason::Why::PeerClosed, {}, "the controller is gone"});
}

void VehicleServer::on_closed(protocol::LineConnection& c, const protocol::CloseReason& why) {
  // A client that never controlled the vehicle leaves nothing behind.
  if (waiting_client(c)) {
    log(fmt::format("{:.1f} s: a client left before its hello", sim_.time_s()));
    drop_waiting(c);
    return;
  }
  // A close this server asked for (bye, the hello timeout) is no dropped link.
  if (&c != controller_.get() || why.why == protocol::CloseReason::Why::Local) return;
  if (why.why == protocol::CloseReason::Why::PeerClosed) {
    log(fmt::format("{:.1f} s: client disconnected", sim_.time_s()));
  } else {
    log(fmt::format("{:.1f} s: client disconnected: {}", sim_.time_s(), why.message));
  }
  cancel_silence_watchdog();
  controller_.reset();
  hello_done_ = false;
  deferred_.clear();
  waiting_.clear();  // nobody to answer
  held_advance_.reset();
  if (sim_.network_up()) trip("link dropped");
}

void VehicleServer::trip(const std::string& reason) {
  const bool tripped_before = sim_.watchdog_tripped();
  if (!tripped_before) {
    sim_.watchdog_trip(reason);
    flush_events();
    // Requests waiting for their cycle will not get it: the vehicle is on its own.
    std::sort(waiting_.begin(), waiting_.end(),
              [](const Waiting& a, const Waiting& b) { return a.request.id < b.request.id; });
    for (const auto& w : waiting_) {
      send(protocol::Err{w.request.id, ErrorCode::NotReady,
                         "the watchdog tripped: the vehicle is surfacing on its own"});
    }
    waiting_.clear();
  }
  // Tripped already (in simulated time, during a lost link the client still
  // advanced through) and the client gone: the vehicle may still be on its
  // way up. While the client is there, its advances move time.
  if (options_.clock == protocol::ClockMode::Lockstep && (!tripped_before || !controller_)) run_alone(std::nullopt);
}

// Lockstep without a client: nobody will ask the simulation to move, so it
// runs on its own (in batches, without blocking the event loop). If trip_at_s
// is set, the watchdog trips then (the link went silent); after the trip it
// runs until the vehicle is at the surface, or autonomous_run_s has passed.
void VehicleServer::run_alone(std::optional<double> trip_at_s) {
  if (running_alone_) return;
  running_alone_ = true;
  alone_until_s_ = sim_.time_s() + options_.autonomous_run_s;
  alone_trip_at_s_ = trip_at_s;
  asio::post(io_, [this] { run_alone_batch(); });
}

// One batch of cycles, then yield to the event loop.
void VehicleServer::run_alone_batch() {
  if (stopped_ || !running_alone_) return;
  // Up is checked at every cycle, so the log says when, not the batch's end.
  const auto up = [this] { return sim_.watchdog_tripped() && sim_.surface_reached(); };
  for (int i = 0; i < 100 && sim_.time_s() < alone_until_s_ && !up(); ++i) {
    step_one();
    if (alone_trip_at_s_ && !sim_.watchdog_tripped() && sim_.time_s() + 1e-9 >= *alone_trip_at_s_) {
      sim_.watchdog_trip(fmt::format("link silent for {:.1f} s", sim_.params().watchdog_s));
      flush_events();
    }
  }
  if (up() || sim_.time_s() >= alone_until_s_) {
    log(fmt::format("{:.1f} s: {}", sim_.time_s(),
                    sim_.surface_reached() ? "at the surface; holding" : "not at the surface in time"));
    running_alone_ = false;
    if (auto held = std::exchange(held_advance_, std::nullopt)) advance(held->id, held->until_s);
    settled();
    return;
  }
  asio::post(io_, [this] { run_alone_batch(); });
}

void VehicleServer::when_settled(std::function<void()> f) {
  settled_waiters_.push_back(std::move(f));
  if (stopped_) return settled();
  // On the wall clock the vehicle moves by itself (tick): after a trip it
  // is settled at the surface, or autonomous_run_s later; tick() says so.
  if (options_.clock == protocol::ClockMode::Wall && sim_.watchdog_tripped() && !sim_.surface_reached()) {
    if (!wall_settle_until_s_) wall_settle_until_s_ = sim_.time_s() + options_.autonomous_run_s;
    return;
  }
  if (!running_alone_) settled();
}

void VehicleServer::check_wall_settled() {
  if (!wall_settle_until_s_ || settled_waiters_.empty()) return;
  const bool up = sim_.surface_reached();
  if (!up && sim_.time_s() < *wall_settle_until_s_) return;
  log(fmt::format("{:.1f} s: {}", sim_.time_s(), up ? "at the surface; holding" : "not at the surface in time"));
  wall_settle_until_s_.reset();
  settled();
}

void VehicleServer::settled() {
  auto waiters = std::move(settled_waiters_);
  settled_waiters_.clear();
  for (auto& f : waiters) asio::post(io_, std::move(f));
}

}  // namespace strata::vehicle
