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
    : io_(io), sim_(sim), options_(std::move(options)), acceptor_(io), tick_timer_(io), silence_timer_(io) {}

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
  if (auto r = start_running(); !r) {
    acceptor_.close(ec);
    return r;
  }
  accept();
  return {};
}

core::Result<void> VehicleServer::start_paired(protocol::LineConnection::Socket client) {
  if (auto r = start_running(); !r) return r;
  admit(std::move(client));
  return {};
}

core::Result<void> VehicleServer::start_running() {
  if (options_.sonar) {
    sonar_ = std::make_unique<SonarServer>(io_, SonarServerOptions{options_.address, options_.sonar_port});
    if (auto r = sonar_->start(); !r) return r;
  }
  if (options_.clock == protocol::ClockMode::Wall) tick();
  return {};
}

void VehicleServer::stop() {
  if (stopped_) return;
  stopped_ = true;
  asio::error_code ignored;
  acceptor_.close(ignored);
  tick_timer_.cancel();
  cancel_silence_watchdog();
  for (auto& w : waiting_clients_) {
    w.hello_timer->cancel();
    w.conn->close("the vehicle is stopping");
  }
  waiting_clients_.clear();
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
      admit(std::move(socket));
    }
    accept();
  });
}

void VehicleServer::admit(protocol::LineConnection::Socket socket) {
  auto c = protocol::LineConnection::create(
      std::move(socket), controller_options(),
      {[this](protocol::LineConnection& conn, const protocol::Frame& frame) { on_line(conn, frame); },
       [this](protocol::LineConnection& conn, const protocol::CloseReason& why) { on_closed(conn, why); }});
  if (controller_ && !controller_->closing()) {
    refuse(*c, "another client controls the vehicle");
  } else if (waiting_clients_.size() >= kMaxWaitingClients) {
    refuse(*c, fmt::format("{} clients are connected without a hello; try again", waiting_clients_.size()));
  } else {
    // It waits for its hello beside any others: the first accepted
    // hello takes the vehicle (server.h, "Hello").
    log(fmt::format("{:.1f} s: client connected", sim_.time_s()));
    auto timer = std::make_unique<asio::steady_timer>(io_);
    arm_hello_timeout(c, *timer);
    waiting_clients_.push_back({c, std::move(timer)});
    c->start();
  }
}

void VehicleServer::refuse(protocol::LineConnection& c, const std::string& why) {
  ++refused_;
  log("refused a client: " + why);
  write(c, protocol::encode(protocol::VehicleMessage{protocol::Err{0, ErrorCode::Busy, why}}));
  c.close_when_written("refused: " + why);
}

std::shared_ptr<protocol::LineConnection> VehicleServer::waiting_client(const protocol::LineConnection& c) const {
  for (const auto& w : waiting_clients_) {
    if (w.conn.get() == &c) return w.conn;
  }
  return nullptr;
}

void VehicleServer::drop_waiting(const protocol::LineConnection& c) {
  auto it = std::find_if(waiting_clients_.begin(), waiting_clients_.end(),
                         [&](const WaitingClient& w) { return w.conn.get() == &c; });
  if (it == waiting_clients_.end()) return;
  it->hello_timer->cancel();
  waiting_clients_.erase(it);
}

void VehicleServer::on_waiting_line(const std::shared_ptr<protocol::LineConnection>& c, const protocol::Frame& frame) {
  if (options_.trace) log("< " + frame.line);
  auto answer = [&](const protocol::Err& e) { write(*c, protocol::encode(protocol::VehicleMessage{e})); };
  if (frame.too_long) {
    answer({protocol::peek_id(frame.line), ErrorCode::TooLong,
            fmt::format("line over {} bytes", protocol::kMaxLineBytes)});
    return;
  }
  auto decoded = protocol::decode_request(frame.line);
  if (!decoded) {
    answer(protocol::to_err(decoded.error()));
    return;
  }
  const protocol::Request& r = decoded.value();
  if (r.verb != protocol::Verb::Hello) {
    answer({r.id, ErrorCode::NotReady, "say hello first"});
    return;
  }
  if (!protocol::speaks_version(r.version)) {
    log(fmt::format("refused hello from '{}': protocol version {}", r.name, r.version));
    answer({r.id, ErrorCode::BadArgument,
            fmt::format("protocol version {} is not spoken here; this vehicle speaks {}", r.version,
                        protocol::spoken_versions())});
    return;
  }
  take_control(c, r);
}

void VehicleServer::take_control(const std::shared_ptr<protocol::LineConnection>& c, const protocol::Request& r) {
  drop_waiting(*c);
  // The others still waiting lose the race: refused, as any client while
  // this one controls the vehicle.
  for (auto& w : std::exchange(waiting_clients_, {})) {
    w.hello_timer->cancel();
    refuse(*w.conn, "another client controls the vehicle");
  }
  controller_ = c;
  hello_done_ = true;
  session_version_ = r.version;
  deferred_.clear();  // replies owed to a previous client are not this one's
  waiting_.clear();
  held_advance_.reset();
  telemetry_.stop();
  last_rx_s_ = sim_.time_s();
  log(fmt::format("{:.1f} s: client '{}' controls the vehicle (protocol {})", sim_.time_s(), r.name, r.version));
  arm_silence_watchdog();
  // The session speaks the version asked for: a version-1 client keeps
  // version 1's lockstep, where each request moves time itself.
  send(protocol::Welcome{r.id, options_.vehicle_name, r.version, options_.clock,
                         sonar_ ? std::optional<std::uint16_t>(sonar_->port()) : std::nullopt,
                         wire_time(sim_.time_s())});
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
  if (auto w = waiting_client(c)) return on_waiting_line(w, frame);
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
    // The session is under way: one hello a connection.
    send(protocol::Err{r.id, ErrorCode::BadArgument,
                       fmt::format("this session said hello already (protocol {})", session_version_)});
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
