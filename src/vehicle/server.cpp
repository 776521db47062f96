#include "vehicle/server.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "protocol/codec.h"
#include "vehicle/execution.h"
#include "vehicle/wire_time.h"

namespace strata::vehicle {

using protocol::ErrorCode;

namespace {

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
    : io_(io),
      sim_(sim),
      options_(std::move(options)),
      acceptor_(io),
      tick_timer_(io),
      silence_timer_(io),
      hello_timer_(io) {}

VehicleServer::~VehicleServer() { stop(); }

void VehicleServer::log(const std::string& line) {
  if (options_.log) options_.log(line);
}

core::Result<void> VehicleServer::start() {
  asio::error_code ec;
  auto address = asio::ip::make_address(options_.address, ec);
  if (ec)
    return core::make_error(core::ErrorCode::InvalidInput, fmt::format("'{}' is not an IP address", options_.address));
  asio::ip::tcp::endpoint endpoint(address, options_.port);
  acceptor_.open(endpoint.protocol(), ec);
  if (!ec) acceptor_.set_option(asio::ip::tcp::acceptor::reuse_address(true), ec);
  if (!ec) acceptor_.bind(endpoint, ec);
  if (!ec) acceptor_.listen(asio::socket_base::max_listen_connections, ec);
  if (ec) {
    return core::make_error(core::ErrorCode::Io,
                            fmt::format("cannot listen on {}:{}: {}", options_.address, options_.port, ec.message()));
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
        held_advance_.reset();
        telemetry_.stop();
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

void VehicleServer::send_clock(const protocol::Ok& ok) {
  if (!controller_ || controller_->closing()) return;
  write(*controller_, protocol::encode(protocol::VehicleMessage{ok}));
}

bool VehicleServer::is_clock_line(const protocol::Frame& frame) const {
  if (frame.too_long || !hello_done_ || session_version_ < 2 || options_.clock != protocol::ClockMode::Lockstep) {
    return false;
  }
  auto decoded = protocol::decode_request(frame.line);
  return decoded.ok() && decoded.value().verb == protocol::Verb::Advance && decoded.value().until_s.has_value();
}

void VehicleServer::write(protocol::LineConnection& c, std::string line) {
  if (c.closing()) return;
  if (options_.trace) log("> " + line.substr(0, line.size() - 1));
  (void)c.send(std::move(line));  // a full queue closes it, and on_closed says so
}

void VehicleServer::on_line(protocol::LineConnection& c, const protocol::Frame& frame) {
  if (&c != controller_.get()) return;
  if (sim_.link_lost() && !is_clock_line(frame)) return;  // lost on the way
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
      telemetry_.set_rate(r.rate_hz, sim_.time_s());
      send(protocol::Ok{r.id, std::nullopt});
      return;
    case Verb::Ping: send(protocol::Pong{r.id, wire_time(sim_.time_s())}); return;
    case Verb::Bye:
      send(protocol::Ok{r.id, std::nullopt});
      c.close_when_written("bye");
      return;
    case Verb::Advance:
      if (session_version_ < 2) {
        send(protocol::Err{
            r.id, ErrorCode::UnknownVerb,
            fmt::format("'advance' is protocol 2; this session speaks {} (say hello ID NAME 2)", session_version_)});
        return;
      }
      // On the wall clock time moves by itself: nothing to do.
      if (options_.clock == protocol::ClockMode::Wall) {
        send(protocol::Ok{r.id, std::nullopt});
        return;
      }
      if (running_alone_ && r.until_s) {
        // The watchdog has the vehicle: time moves for the client once it is
        // done. One at a time: an earlier one is answered with the time now.
        if (held_advance_) send_clock(protocol::Ok{held_advance_->id, wire_time(sim_.time_s())});
        held_advance_ = r;
        return;
      }
      advance(r.id, r.until_s);
      return;
    default: on_call(r); return;
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
  protocol::Welcome welcome{r.id,
                            options_.vehicle_name,
                            r.version,
                            options_.clock,
                            sonar_ ? std::optional<std::uint16_t>(sonar_->port()) : std::nullopt,
                            wire_time(sim_.time_s())};
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
    send(protocol::Err{r.id, ErrorCode::NotReady, "the watchdog tripped: the vehicle is surfacing on its own"});
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
    const auto cycles =
        std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::llround(out.sleep_s / sim_.params().cycle_s)));
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

}  // namespace strata::vehicle
