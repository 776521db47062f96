#include "vehicle/server.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "protocol/codec.h"
#include "vehicle/execution.h"

namespace strata::vehicle {

using protocol::ErrorCode;

namespace {

// Simulated time on the wire, rounded to the microsecond: cycle * 0.1 is not
// exact in binary, and "5.6000000000000005" helps nobody.
double wire_time(double t_s) { return std::round(t_s * 1e6) / 1e6; }

// The controller's connection: lines up to the protocol's maximum (a longer
// one is answered `err ID too_long`), and a write queue bounded far above
// what one lockstep instant can queue (telemetry through a long sleep), so
// that only a client that stopped reading reaches it.
protocol::LineConnectionOptions controller_options() {
  protocol::LineConnectionOptions o;
  o.max_line_bytes = protocol::kMaxLineBytes;
  o.overlong = protocol::LineConnectionOptions::Overlong::Deliver;
  o.max_queue_bytes = std::size_t{64} << 20;
  o.when_full = protocol::LineConnectionOptions::WhenFull::Close;
  return o;
}

}  // namespace

VehicleServer::VehicleServer(asio::io_context& io, Simulation& sim, ServerOptions options)
    : io_(io), sim_(sim), options_(std::move(options)), acceptor_(io), tick_timer_(io),
      silence_timer_(io), hello_timer_(io) {}

VehicleServer::~VehicleServer() { stop(); }

void VehicleServer::log(const std::string& line) {
  if (options_.log) options_.log(line);
}

core::Result<void> VehicleServer::start() {
  asio::error_code ec;
  auto address = asio::ip::make_address(options_.address, ec);
  if (ec) return core::make_error(core::ErrorCode::InvalidInput, fmt::format("'{}' is not an IP address", options_.address));
  asio::ip::tcp::endpoint endpoint(address, options_.port);
  acceptor_.open(endpoint.protocol(), ec);
  if (!ec) acceptor_.set_option(asio::ip::tcp::acceptor::reuse_address(true), ec);
  if (!ec) acceptor_.bind(endpoint, ec);
  if (!ec) acceptor_.listen(asio::socket_base::max_listen_connections, ec);
  if (ec) {
    return core::make_error(core::ErrorCode::Io, fmt::format("cannot listen on {}:{}: {}",
                                                             options_.address, options_.port, ec.message()));
  }
  port_ = acceptor_.local_endpoint().port();
  if (options_.sonar) {
    sonar_ = std::make_unique<SonarServer>(io_, SonarServerOptions{options_.address, options_.sonar_port});
    if (auto r = sonar_->start(); !r) {
      acceptor_.close(ec);
      return r;
    }
  }
  accept();
  if (options_.clock == protocol::ClockMode::Wall) tick();
  return {};
}

void VehicleServer::stop() {
  if (stopped_) return;
  stopped_ = true;
  asio::error_code ignored;
  acceptor_.close(ignored);
  tick_timer_.cancel();
  silence_timer_.cancel();
  hello_timer_.cancel();
  waiting_.clear();
  if (controller_) controller_->close("the vehicle is stopping");
  controller_.reset();
  if (sonar_) sonar_->end(sim_.time_s(), "the vehicle is stopping");
  settled();
}

void VehicleServer::accept() {
  acceptor_.async_accept([this](const asio::error_code& e, asio::ip::tcp::socket socket) {
    if (stopped_) return;
    if (!e) {
      asio::error_code ignored;
      socket.set_option(asio::ip::tcp::no_delay(true), ignored);
      auto c = protocol::LineConnection::create(
          std::move(socket), controller_options(),
          {[this](protocol::LineConnection& conn, const protocol::Frame& frame) { on_line(conn, frame); },
           [this](protocol::LineConnection& conn, const protocol::CloseReason& why) { on_closed(conn, why); }});
      if (controller_ && !controller_->closing()) {
        ++refused_;
        log("refused a second client: one client controls the vehicle");
        write(*c, protocol::encode(protocol::VehicleMessage{
                      protocol::Err{0, ErrorCode::Busy, "another client controls the vehicle"}}));
        c->close_when_written("refused: another client controls the vehicle");
      } else {
        controller_ = c;
        hello_done_ = false;
        session_version_ = 0;
        deferred_.clear();  // replies owed to a previous client are not this one's
        waiting_.clear();
        telemetry_rate_hz_ = 0.0;
        last_rx_s_ = sim_.time_s();
        log(fmt::format("{:.1f} s: client connected", sim_.time_s()));
        c->start();
        arm_silence_watchdog();
        arm_hello_timeout(c);
      }
    }
    accept();
  });
}

void VehicleServer::send(const protocol::VehicleMessage& m) {
  if (!controller_ || controller_->closing()) return;
  if (sim_.link_lost()) return;  // the link is silent both ways
  write(*controller_, protocol::encode(m));
}

void VehicleServer::write(protocol::LineConnection& c, std::string line) {
  if (c.closing()) return;
  if (options_.trace) log("> " + line.substr(0, line.size() - 1));
  (void)c.send(std::move(line));  // a full queue closes it, and on_closed says so
}

void VehicleServer::on_line(protocol::LineConnection& c, const protocol::Frame& frame) {
  if (&c != controller_.get()) return;
  if (sim_.link_lost()) return;  // lost on the way
  last_rx_s_ = sim_.time_s();
  arm_silence_watchdog();
  if (options_.trace) log("< " + frame.line);
  if (frame.too_long) {
    log(fmt::format("rejected a line over {} bytes", protocol::kMaxLineBytes));
    send(protocol::Err{protocol::peek_id(frame.line), ErrorCode::TooLong,
                       fmt::format("line over {} bytes", protocol::kMaxLineBytes)});
    return;
  }
  auto decoded = protocol::decode_request(frame.line);
  if (!decoded) {
    const auto& err = decoded.error();
    log(fmt::format("rejected line: {}: {}", err.message, frame.line.substr(0, 120)));
    send(protocol::to_err(err));
    return;
  }
  on_request(c, decoded.value());
}

void VehicleServer::on_request(protocol::LineConnection& c, const protocol::Request& r) {
  using protocol::Verb;
  if (r.verb == Verb::Hello) {
    on_hello(r);
    return;
  }
  if (!hello_done_) {
    send(protocol::Err{r.id, ErrorCode::NotReady, "say hello first"});
    return;
  }
  switch (r.verb) {
    case Verb::Telemetry:
      // The first sample comes one period after the request.
      telemetry_rate_hz_ = r.rate_hz;
      next_telemetry_s_ = r.rate_hz > 0 ? sim_.time_s() + 1.0 / r.rate_hz : 0.0;
      send(protocol::Ok{r.id});
      return;
    case Verb::Ping:
      send(protocol::Pong{r.id, wire_time(sim_.time_s())});
      return;
    case Verb::Bye:
      send(protocol::Ok{r.id});
      c.close_when_written("bye");
      return;
    case Verb::Advance:
      if (session_version_ < 2) {
        send(protocol::Err{r.id, ErrorCode::UnknownVerb,
                           fmt::format("'advance' is protocol 2; this session speaks {} (say hello ID NAME 2)",
                                       session_version_)});
        return;
      }
      // On the wall clock time moves by itself: nothing to do.
      if (options_.clock == protocol::ClockMode::Wall) {
        send(protocol::Ok{r.id});
        return;
      }
      advance(r.id);
      return;
    default:
      on_call(r);
      return;
  }
}

void VehicleServer::on_hello(const protocol::Request& r) {
  if (!protocol::speaks_version(r.version)) {
    log(fmt::format("refused hello from '{}': protocol version {}", r.name, r.version));
    send(protocol::Err{r.id, ErrorCode::BadArgument,
                       fmt::format("protocol version {} is not spoken here; this vehicle speaks {}", r.version,
                                   protocol::spoken_versions())});
    return;
  }
  hello_done_ = true;
  session_version_ = r.version;
  hello_timer_.cancel();
  // The session speaks the version asked for: a version-1 client keeps
  // version 1's lockstep, where each request moves time itself.
  protocol::Welcome welcome{r.id, options_.vehicle_name, r.version, options_.clock,
                            sonar_ ? std::optional<std::uint16_t>(sonar_->port()) : std::nullopt};
  send(welcome);
}

bool VehicleServer::in_flight(protocol::RequestId id) const {
  for (const auto& w : waiting_) {
    if (w.request.id == id) return true;
  }
  for (const auto& d : deferred_) {
    if (d.id == id) return true;
  }
  return false;
}

// exec, ask and ood.
void VehicleServer::on_call(const protocol::Request& r) {
  using protocol::Verb;
  if (running_alone_) {
    // The watchdog has the vehicle; stepping for a client too would make the
    // run depend on how the two interleave.
    send(protocol::Err{r.id, ErrorCode::NotReady,
                       "the watchdog tripped: the vehicle is surfacing on its own"});
    return;
  }
  if (in_flight(r.id)) {
    send(protocol::Err{r.id, ErrorCode::DuplicateId, fmt::format("request {} is already in flight", r.id)});
    return;
  }
  Outcome out = execute(sim_, r);
  if (out.refused) {
    log(fmt::format("{:.1f} s: refused {} {}: {}", sim_.time_s(), protocol::verb_name(r.verb), r.name, out.message));
    send(protocol::Err{r.id, *out.refused, out.message});
    return;
  }
  if (!out.value && r.verb != Verb::Ask) {
    std::string text = fmt::format("{} {} failed: {}", protocol::verb_name(r.verb), r.name, out.message);
    log(fmt::format("{:.1f} s: {}", sim_.time_s(), text));
    send(protocol::Event{wire_time(sim_.time_s()), text});
  }
  if (options_.clock == protocol::ClockMode::Lockstep) {
    // A request costs at least one cycle; sleep costs its duration.
    const auto cycles = std::max<std::uint64_t>(
        1, static_cast<std::uint64_t>(std::llround(out.sleep_s / sim_.params().cycle_s)));
    waiting_.push_back(Waiting{r, out.value, sim_.cycle() + cycles});
    // Protocol 1 has no advance: the request moves time itself, alone.
    if (session_version_ < 2) advance(std::nullopt);
    return;
  }
  if (out.sleep_s > 0) {
    reply_later(r.id, sim_.time_s() + out.sleep_s);
    return;
  }
  double t = wire_time(sim_.time_s());
  if (r.verb == Verb::Ask) {
    send(protocol::Answer{r.id, out.value, t});
  } else {
    send(protocol::Done{r.id, out.value, t});
  }
}

// Lockstep: steps every waiting request together until one is due, answers
// all that are due, then the advance itself. With nothing waiting, time does
// not move.
void VehicleServer::advance(std::optional<protocol::RequestId> advance_id) {
  if (!waiting_.empty()) {
    std::uint64_t next_due = waiting_.front().due_cycle;
    for (const auto& w : waiting_) next_due = std::min(next_due, w.due_cycle);
    while (sim_.cycle() < next_due && !sim_.link_lost()) step_one();
  }
  if (sim_.link_lost()) {
    // The replies would be lost with the link. Nobody can ask the simulation
    // to move now: it runs on alone, and the watchdog trips after
    // watchdog_s of silence (run_alone trips it in simulated time).
    waiting_.clear();
    silence_timer_.cancel();
    if (!running_alone_) {
      log(fmt::format("{:.1f} s: link lost (scenario)", sim_.time_s()));
      run_alone(sim_.time_s() + sim_.params().watchdog_s);
    }
    return;
  }
  reply_due();
  if (advance_id) send(protocol::Ok{*advance_id});
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
  after_step();
}

void VehicleServer::after_step() {
  flush_events();
  flush_pings();
  if (telemetry_rate_hz_ > 0 && sim_.time_s() + 1e-9 >= next_telemetry_s_) {
    auto t = sim_.telemetry();
    protocol::Telemetry m;
    m.sim_time_s = wire_time(t.time_s);
    // Rounded to what the instruments resolve: 0.1 mm, 0.1 mm/s, 0.01 N.
    auto round_to = [](std::optional<double> v, double step) -> std::optional<double> {
      if (!v) return v;
      return std::round(*v / step) * step;
    };
    m.depth_m = round_to(t.measured_depth_m, 1e-4);
    m.filtered_depth_m = round_to(t.filtered_depth_m, 1e-4);
    m.rate_mps = round_to(t.rate_mps, 1e-4);
    m.thrust_n = round_to(t.thrust_n, 1e-2);
    m.setpoint_m = t.setpoint_m;
    m.heading_deg = std::fmod(*round_to(t.heading_deg, 1e-2), 360.0);  // 359.996 -> 0, not 360
    m.extras["true_depth"] = fmt::format("{:.4f}", t.depth_m);
    m.extras["mode"] = std::string(to_string(t.mode));
    send(m);
    next_telemetry_s_ += 1.0 / telemetry_rate_hz_;
    if (next_telemetry_s_ < sim_.time_s()) next_telemetry_s_ = sim_.time_s() + 1.0 / telemetry_rate_hz_;
  }
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

void VehicleServer::reply_later(protocol::RequestId id, double until_s) {
  deferred_.push_back({id, until_s});
}

// A client that connects and says nothing must not hold the vehicle: every
// client after it would be refused as busy for ever.
void VehicleServer::arm_hello_timeout(const std::shared_ptr<protocol::LineConnection>& c) {
  if (options_.hello_timeout_s <= 0) return;
  hello_timer_.expires_after(std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(std::min(options_.hello_timeout_s, 86400.0))));
  hello_timer_.async_wait([this, weak = std::weak_ptr<protocol::LineConnection>(c)](const asio::error_code& e) {
    auto conn = weak.lock();
    if (e || stopped_ || hello_done_ || !conn || conn != controller_ || conn->closing()) return;
    const std::string why = fmt::format("no hello within {} s: closing this connection", options_.hello_timeout_s);
    log(fmt::format("{:.1f} s: {}; the next client will be served", sim_.time_s(), why));
    write(*conn, protocol::encode(protocol::VehicleMessage{protocol::Err{0, ErrorCode::NotReady, why}}));
    conn->close_when_written(why);
    controller_.reset();
    silence_timer_.cancel();
  });
}

void VehicleServer::arm_silence_watchdog() {
  if (options_.clock != protocol::ClockMode::Lockstep) return;  // wall: checked per tick
  double silence_s = std::min(sim_.params().watchdog_s, 86400.0);  // a day is "never" here
  silence_timer_.expires_after(std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(silence_s)));
  silence_timer_.async_wait([this](const asio::error_code& e) {
    if (e || stopped_ || !controller_ || controller_->closing() || !sim_.network_up()) return;
    trip(fmt::format("link silent for {:.1f} s", sim_.params().watchdog_s));
  });
}

void VehicleServer::controller_gone() {
  if (!controller_) return;
  auto c = controller_;
  c->close("the controller is gone");
  on_closed(*c, protocol::CloseReason{protocol::CloseReason::Why::PeerClosed, {}, "the controller is gone"});
}

void VehicleServer::on_closed(protocol::LineConnection& c, const protocol::CloseReason& why) {
  // A close this server asked for (bye, the hello timeout) is no dropped link.
  if (&c != controller_.get() || why.why == protocol::CloseReason::Why::Local) return;
  if (why.why == protocol::CloseReason::Why::PeerClosed) {
    log(fmt::format("{:.1f} s: client disconnected", sim_.time_s()));
  } else {
    log(fmt::format("{:.1f} s: client disconnected: {}", sim_.time_s(), why.message));
  }
  silence_timer_.cancel();
  hello_timer_.cancel();
  controller_.reset();
  deferred_.clear();
  waiting_.clear();  // nobody to answer
  if (sim_.network_up()) trip("link dropped");
}

void VehicleServer::trip(const std::string& reason) {
  if (sim_.watchdog_tripped()) return;
  sim_.watchdog_trip(reason);
  flush_events();
  // Requests waiting for their cycle will not get it: the vehicle is on its own.
  std::sort(waiting_.begin(), waiting_.end(),
            [](const Waiting& a, const Waiting& b) { return a.request.id < b.request.id; });
  for (const auto& w : waiting_) {
    send(protocol::Err{w.request.id, ErrorCode::NotReady, "the watchdog tripped: the vehicle is surfacing on its own"});
  }
  waiting_.clear();
  if (options_.clock == protocol::ClockMode::Lockstep) run_alone(std::nullopt);
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
  for (int i = 0; i < 100 && sim_.time_s() < alone_until_s_; ++i) {
    step_one();
    if (alone_trip_at_s_ && !sim_.watchdog_tripped() && sim_.time_s() + 1e-9 >= *alone_trip_at_s_) {
      sim_.watchdog_trip(fmt::format("link silent for {:.1f} s", sim_.params().watchdog_s));
      flush_events();
    }
  }
  if ((sim_.watchdog_tripped() && sim_.surface_reached()) || sim_.time_s() >= alone_until_s_) {
    log(fmt::format("{:.1f} s: {}", sim_.time_s(),
                    sim_.surface_reached() ? "at the surface; holding" : "not at the surface in time"));
    running_alone_ = false;
    settled();
    return;
  }
  asio::post(io_, [this] { run_alone_batch(); });
}

void VehicleServer::when_settled(std::function<void()> f) {
  settled_waiters_.push_back(std::move(f));
  if (!running_alone_ || stopped_) settled();
}

void VehicleServer::settled() {
  auto waiters = std::move(settled_waiters_);
  settled_waiters_.clear();
  for (auto& f : waiters) asio::post(io_, std::move(f));
}

void VehicleServer::tick() {
  auto period = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(sim_.params().cycle_s / options_.speed));
  // Against the previous expiry, not now: the loop must not drift by the
  // time each tick takes.
  if (tick_timer_.expiry() == asio::steady_timer::time_point{}) {
    tick_timer_.expires_after(period);
  } else {
    tick_timer_.expires_at(tick_timer_.expiry() + period);
  }
  tick_timer_.async_wait([this](const asio::error_code& e) {
    if (e || stopped_) return;
    step_one();
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
