#include "tactical/vehicle_link.h"

#include <cmath>
#include <vector>

#include <fmt/format.h>

namespace strata::tactical {

using core::ErrorCode;
using core::make_error;

namespace {

// Lines up to the protocol's maximum (a longer one is reported as garbage and
// skipped); a write queue no client fills unless the vehicle stopped reading.
protocol::LineConnectionOptions link_options() {
  protocol::LineConnectionOptions o;
  o.max_line_bytes = protocol::kMaxLineBytes;
  o.overlong = protocol::LineConnectionOptions::Overlong::Deliver;
  o.max_queue_bytes = std::size_t{1} << 20;
  o.when_full = protocol::LineConnectionOptions::WhenFull::Close;
  return o;
}

}  // namespace

std::string describe(const protocol::Request& request) {
  std::string line = protocol::encode(request);
  // "exec 7 sleep 1\n" -> "exec sleep 1": the id says nothing to a person.
  std::string out(protocol::verb_name(request.verb));
  auto first = line.find(' ');
  auto second = first == std::string::npos ? std::string::npos : line.find(' ', first + 1);
  if (second != std::string::npos) out += line.substr(second, line.size() - second - 1);
  return out;
}

std::string refusal_text(std::string_view what, const protocol::Err& err) {
  return fmt::format("vehicle refused `{}` (request {}): {}: {}", what, err.id, protocol::code_name(err.code),
                     err.message);
}

std::shared_ptr<VehicleLink> VehicleLink::create(asio::io_context& io, LinkOptions options) {
  return std::shared_ptr<VehicleLink>(new VehicleLink(io, std::move(options)));
}

VehicleLink::VehicleLink(asio::io_context& io, LinkOptions options)
    : io_(io), options_(std::move(options)), socket_(io), connect_timer_(io), advance_timer_(io) {}

VehicleLink::~VehicleLink() { drop_connection("the link is gone"); }

void VehicleLink::drop_connection(const std::string& why) {
  asio::error_code ignored;
  socket_.close(ignored);
  if (connection_) connection_->close(why);
  connection_.reset();
}

void VehicleLink::connect(const std::function<void(core::Result<protocol::Welcome>)>& done) {
  reconnects_left_ = options_.reconnect_attempts;
  closing_ = false;
  start_connect(done);
}

void VehicleLink::start_connect(const std::function<void(core::Result<protocol::Welcome>)>& done) {
  auto self = this->self();
  asio::error_code ec;
  auto address = asio::ip::make_address(options_.host == "localhost" ? "127.0.0.1" : options_.host, ec);
  if (ec) {
    done(make_error(ErrorCode::Io, fmt::format("'{}' is not an IP address", options_.host)));
    return;
  }
  asio::ip::tcp::endpoint endpoint(address, options_.port);
  drop_connection("connecting again");
  socket_ = asio::ip::tcp::socket(io_);
  auto finished = arm_connect_timer(fmt::format("the vehicle at {}:{}", options_.host, options_.port), done);
  socket_.async_connect(endpoint, [this, self, finished, done](const asio::error_code& e) {
    if (*finished) return;
    if (e) {
      *finished = true;
      connect_timer_.cancel();
      done(make_error(ErrorCode::Io,
                      fmt::format("cannot reach the vehicle at {}:{}: {}", options_.host, options_.port, e.message())));
      return;
    }
    asio::ip::tcp::no_delay nodelay(true);
    asio::error_code ignored;
    socket_.set_option(nodelay, ignored);
    say_hello(std::move(socket_), finished, done);
  });
}

void VehicleLink::connect_paired(protocol::LineConnection::Socket socket,
                                 std::function<void(core::Result<protocol::Welcome>)> done) {
  reconnects_left_ = 0;  // nothing to connect to again
  closing_ = false;
  drop_connection("connecting again");
  auto finished = arm_connect_timer("the embedded vehicle", done);
  say_hello(std::move(socket), finished, std::move(done));
}

std::shared_ptr<bool> VehicleLink::arm_connect_timer(const std::string& vehicle,
                                                     const std::function<void(core::Result<protocol::Welcome>)>& done) {
  auto self = this->self();
  auto finished = std::make_shared<bool>(false);
  connect_timer_.expires_after(options_.connect_timeout);
  connect_timer_.async_wait([this, self, finished, done, vehicle](const asio::error_code& e) {
    if (e || *finished) return;
    *finished = true;
    auto error = make_error(ErrorCode::Timeout,
                            fmt::format("no answer from {} within {} ms", vehicle, options_.connect_timeout.count()));
    abandon(error);
    done(error);
  });
  return finished;
}

void VehicleLink::say_hello(protocol::LineConnection::Socket socket, const std::shared_ptr<bool>& finished,
                            std::function<void(core::Result<protocol::Welcome>)> done) {
  connected_ = true;
  std::weak_ptr<VehicleLink> weak = self();
  connection_ =
      protocol::LineConnection::create(std::move(socket), link_options(),
                                       {[weak](protocol::LineConnection&, const protocol::Frame& frame) {
                                          if (auto link = weak.lock()) link->handle_line(frame);
                                        },
                                        [weak](protocol::LineConnection& c, const protocol::CloseReason& why) {
                                          if (auto link = weak.lock()) link->connection_closed(c, why);
                                        }});
  connection_->start();
  // This handler is kept in pending_, inside the link: it must not hold
  // `self`, or the link would own itself.
  protocol::Request hello = protocol::make_hello(0, options_.client_name);
  hello.version = options_.protocol_version;
  std::string what = describe(hello);
  send(
      std::move(hello),
      [this, finished, done, what](core::Result<protocol::VehicleMessage> r) {
        if (*finished) return;
        *finished = true;
        connect_timer_.cancel();
        // A hello that fails ends this connection: a refused or foreign
        // vehicle is not a lost link to reconnect to.
        auto refuse = [&](core::Error error) {
          abandon(error);
          done(std::move(error));
        };
        if (!r) {
          refuse(r.error());
          return;
        }
        if (auto* err = std::get_if<protocol::Err>(&r.value())) {
          refuse(make_error(ErrorCode::Protocol, refusal_text(what, *err)));
          return;
        }
        if (auto* w = std::get_if<protocol::Welcome>(&r.value())) {
          // The session's version: the one asked for, or an older one
          // we speak (a version-1 vehicle says 1 whatever it is asked).
          if (!protocol::speaks_version(w->version) || w->version > options_.protocol_version) {
            refuse(make_error(ErrorCode::Protocol,
                              fmt::format("vehicle speaks protocol {}, we asked for {} (we speak {})", w->version,
                                          options_.protocol_version, protocol::spoken_versions())));
            return;
          }
          session_version_ = w->version;
          barrier_ = w->clock == protocol::ClockMode::Lockstep && w->version >= 2;
          // A vehicle that tells its time in the welcome also takes a
          // bounded advance (docs/protocol.md §8); one that does not gets
          // wall-clock timeouts only.
          sim_now_ = w->sim_time_s;
          bounded_ = barrier_ && w->sim_time_s.has_value();
          done(*w);
          return;
        }
        refuse(make_error(ErrorCode::Protocol, "vehicle answered hello with something else"));
      },
      options_.connect_timeout);
}

protocol::RequestId VehicleLink::send(protocol::Request request, ReplyHandler handler,
                                      std::optional<std::chrono::milliseconds> timeout,
                                      std::optional<double> sim_timeout_s) {
  request.id = next_id_++;
  std::string what = describe(request);
  if (!connected_) {
    // Report asynchronously, like every other outcome, so callers see one order.
    asio::post(io_, [handler = std::move(handler), what] {
      handler(make_error(ErrorCode::Closed, fmt::format("cannot send `{}`: no link to the vehicle", what)));
    });
    return request.id;
  }
  Pending p;
  p.handler = std::move(handler);
  p.what = what;
  p.timed = request.verb == protocol::Verb::Exec || request.verb == protocol::Verb::Ask ||
            request.verb == protocol::Verb::Ood;
  p.timer = std::make_unique<asio::steady_timer>(io_);
  auto wait = timeout.value_or(options_.reply_timeout);
  p.wait = wait;
  if (bounded_ && p.timed && sim_now_ && sim_timeout_s && std::isfinite(*sim_timeout_s) && *sim_timeout_s > 0) {
    p.sim_timeout_s = *sim_timeout_s;
    p.sim_deadline_s = *sim_now_ + *sim_timeout_s;
    // Simulated time decides; the wall clock only catches a dead vehicle.
    wait = std::max(wait, options_.stall_timeout);
    p.wait = wait;
  }
  p.timer->expires_after(wait);
  auto id = request.id;
  auto self = shared_from_this();
  p.timer->async_wait([this, self, id, wait, what](const asio::error_code& e) {
    if (e) return;
    complete(id, make_error(ErrorCode::Timeout,
                            fmt::format("no reply to `{}` (request {}) within {} ms", what, id, wait.count())));
  });
  pending_.emplace(id, std::move(p));
  // The check first: it runs before the connection's posted write, so an
  // advance it sends for this request leaves in the same write (one
  // sendmsg, one wake-up of the vehicle) rather than after it.
  note_activity();
  write(protocol::encode(request));
  return id;
}

void VehicleLink::complete(protocol::RequestId id, core::Result<protocol::VehicleMessage> result) {
  auto it = pending_.find(id);
  if (it == pending_.end()) return;
  ReplyHandler handler = std::move(it->second.handler);
  it->second.timer->cancel();
  pending_.erase(it);
  handler(std::move(result));
  note_activity();
}

void VehicleLink::deliver(protocol::RequestId id, core::Result<protocol::VehicleMessage> result) {
  auto it = pending_.find(id);
  if (it == pending_.end()) return;
  if (barrier_ && it->second.timed) {
    // The rest of this instant's replies may still be on the way; handing
    // this one over now would let the calls it causes race them.
    held_.emplace_back(id, std::move(result));
    if (!advance_id_) note_activity();  // an err that came before any advance: one fetches it
    return;
  }
  complete(id, std::move(result));
}

// A check posted after each thing that may issue calls; only the newest acts,
// so an advance goes once the handlers that issued calls, and everything
// posted before the check, have run.
void VehicleLink::note_activity() {
  if (!barrier_) return;
  const std::uint64_t generation = ++activity_;
  asio::post(io_, [weak = std::weak_ptr<VehicleLink>(self()), generation] {
    if (auto link = weak.lock()) link->maybe_advance(generation);
  });
}

void VehicleLink::maybe_advance(std::uint64_t generation) {
  if (generation != activity_ || !barrier_ || !connected_ || holds() > 0 || advance_id_) return;
  bool timed = false;
  std::chrono::milliseconds wait{0};
  std::optional<double> until;
  for (const auto& [id, p] : pending_) {
    if (!p.timed) continue;
    timed = true;
    wait = std::max(wait, p.wait);
    if (p.sim_deadline_s && (!until || *p.sim_deadline_s < *until)) until = p.sim_deadline_s;
  }
  if (!timed) return;  // nothing waits for simulated time
  const protocol::RequestId id = next_id_++;
  advance_id_ = id;
  ++advances_sent_;
  // The vehicle answers an advance once a request is due: no later than the
  // longest of the requests' own timeouts. Those report a silent vehicle
  // (their timers started first); this one only lets the link go on, so it
  // says nothing (a wall-clock race must not reach the mission log).
  auto self = shared_from_this();
  advance_timer_.expires_after(wait);
  advance_timer_.async_wait([this, self, id](const asio::error_code& e) {
    if (e || advance_id_ != id) return;
    finish_advance();
  });
  write(protocol::encode(protocol::make_advance(id, until)));
}

void VehicleLink::finish_advance(std::optional<double> sim_time_s) {
  advance_id_.reset();
  advance_timer_.cancel();
  // The instant's time first: a handler below may send a request, whose
  // deadline counts from now.
  if (sim_time_s) saw_time(*sim_time_s);
  auto held = std::move(held_);
  held_.clear();
  for (auto& [id, result] : held) complete(id, std::move(result));
  if (sim_time_s) {
    std::vector<protocol::RequestId> late;
    for (const auto& [id, p] : pending_) {  // a std::map: in id order
      if (p.sim_deadline_s && *p.sim_deadline_s <= *sim_now_ + 1e-9) late.push_back(id);
    }
    for (protocol::RequestId id : late) {
      auto it = pending_.find(id);
      if (it == pending_.end()) continue;  // a handler before it ended it
      const std::string what = it->second.what;
      const double waited = it->second.sim_timeout_s;
      complete(
          id, make_error(ErrorCode::Timeout,
                         fmt::format("no reply to `{}` (request {}) within {} s of simulated time", what, id, waited)));
    }
  }
  note_activity();
}

void VehicleLink::saw_time(double sim_time_s) {
  if (!sim_now_ || sim_time_s > *sim_now_) sim_now_ = sim_time_s;
}

void VehicleLink::write(std::string line) {
  if (options_.tap) {
    std::string_view text(line);
    if (!text.empty() && text.back() == '\n') text.remove_suffix(1);
    options_.tap(true, text);
  }
  if (!connected_ || !connection_) return;
  // A full queue closes the connection; connection_closed says so.
  (void)connection_->send(std::move(line));
}

void VehicleLink::connection_closed(protocol::LineConnection& c, const protocol::CloseReason& why) {
  if (&c != connection_.get()) return;
  using Why = protocol::CloseReason::Why;
  switch (why.why) {
    case Why::PeerClosed: lost("the vehicle closed the link"); return;
    case Why::ReadError: lost(fmt::format("link to the vehicle failed: {}", why.error.message())); return;
    case Why::WriteError: lost(fmt::format("cannot write to the vehicle: {}", why.error.message())); return;
    default: lost(fmt::format("link to the vehicle closed: {}", why.message)); return;
  }
}

void VehicleLink::handle_line(const protocol::Frame& frame) {
  if (options_.tap && !frame.too_long) options_.tap(false, frame.line);
  if (frame.too_long) {
    if (on_garbage_) on_garbage_(fmt::format("a line over {} bytes (discarded)", protocol::kMaxLineBytes));
    return;
  }
  auto decoded = protocol::decode_vehicle_message(frame.line);
  if (!decoded) {
    if (on_garbage_) on_garbage_(fmt::format("{}: {}", decoded.error().message, frame.line));
    // A malformed reply to a request in flight ends that request now,
    // rather than at its timeout.
    auto id = decoded.error().id;
    if (id != 0 && advance_id_ == id) {
      finish_advance();
    } else if (id != 0 && pending_.count(id)) {
      deliver(id, make_error(ErrorCode::Protocol,
                             fmt::format("malformed reply from the vehicle: {}", decoded.error().message)));
    }
    return;
  }
  protocol::VehicleMessage& msg = decoded.value();
  if (auto* t = std::get_if<protocol::Telemetry>(&msg)) {
    if (on_telemetry_) on_telemetry_(*t);
    return;
  }
  if (auto* ev = std::get_if<protocol::Event>(&msg)) {
    if (on_event_) on_event_(*ev);
    return;
  }
  if (std::holds_alternative<protocol::Heartbeat>(msg)) return;
  if (auto* err = std::get_if<protocol::Err>(&msg)) {
    std::string text = fmt::format("vehicle error {}: {}", protocol::code_name(err->code), err->message);
    if (err->id == 0) {
      if (err->code == protocol::ErrorCode::Busy) {
        fail_all(make_error(ErrorCode::Protocol, text));
      } else if (on_garbage_) {
        on_garbage_(text);
      }
      return;
    }
    if (advance_id_ == err->id) {
      if (on_garbage_) on_garbage_(fmt::format("vehicle refused advance: {}", text));
      finish_advance();
      return;
    }
    // The vehicle's answer to that request: its handler reads the code.
    deliver(err->id, std::move(msg));
    return;
  }
  auto id = protocol::reply_id(msg);
  if (id && advance_id_ == *id) {
    const auto* ok = std::get_if<protocol::Ok>(&msg);
    finish_advance(ok ? ok->sim_time_s : std::nullopt);  // the end of the instant
    return;
  }
  if (const auto* d = std::get_if<protocol::Done>(&msg)) saw_time(d->sim_time_s);
  if (const auto* a = std::get_if<protocol::Answer>(&msg)) saw_time(a->sim_time_s);
  if (const auto* p = std::get_if<protocol::Pong>(&msg)) saw_time(p->sim_time_s);
  if (!id || !pending_.count(*id)) {
    if (on_garbage_) on_garbage_(fmt::format("a reply for no request in flight: {}", frame.line));
    return;
  }
  deliver(*id, std::move(msg));
}

void VehicleLink::fail_all(const core::Error& error) {
  // Replies held for an advance that will not end are lost with the rest.
  held_.clear();
  advance_id_.reset();
  advance_timer_.cancel();
  auto pending = std::move(pending_);
  pending_.clear();
  for (auto& [id, p] : pending) {
    p.timer->cancel();
    p.handler(make_error(error.code, fmt::format("`{}` (request {}) failed: {}", p.what, id, error.message)));
  }
}

void VehicleLink::end_session() {
  connected_ = false;
  sim_now_.reset();
  bounded_ = false;
  barrier_ = false;
  session_version_ = 0;
}

void VehicleLink::lost(const std::string& why) {
  if (!connected_) return;
  end_session();
  drop_connection(why);
  fail_all(make_error(ErrorCode::Closed, why));
  try_reconnect(why);
}

void VehicleLink::try_reconnect(const std::string& why) {
  if (closing_) return;
  if (reconnects_left_ <= 0) {
    if (on_lost_) on_lost_(make_error(ErrorCode::Closed, why));
    return;
  }
  --reconnects_left_;
  auto self = shared_from_this();
  auto timer = std::make_shared<asio::steady_timer>(io_, options_.reconnect_delay);
  timer->async_wait([this, self, timer, why](const asio::error_code& e) {
    if (e || closing_) return;
    start_connect([this, self, why](const core::Result<protocol::Welcome>& r) {
      if (r) {
        reconnects_left_ = options_.reconnect_attempts;
      } else {
        try_reconnect(why);
      }
    });
  });
}

void VehicleLink::abandon(const core::Error& error) {
  end_session();
  reconnects_left_ = 0;
  drop_connection(error.message);
  fail_all(error);
}

void VehicleLink::close() {
  closing_ = true;
  end_session();
  connect_timer_.cancel();
  drop_connection("the link was closed");
  fail_all(make_error(ErrorCode::Closed, "the link was closed"));
}

}  // namespace strata::tactical
