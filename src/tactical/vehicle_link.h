#pragma once
// The Tactical level's end of the link to the Execution level: one TCP
// connection, non-blocking on an Asio io_context (one thread), speaking
// protocol v1. Several requests may be in flight; each has its own reply
// timeout (wall time: in lockstep the vehicle answers in microseconds, so a
// silent vehicle is a lost link, not a slow one).
//
// Threads: every method must be called on the io_context's thread, and every
// handler runs there.
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include <array>
#include <deque>

#include <asio.hpp>

#include "core/result.h"
#include "protocol/codec.h"
#include "protocol/framer.h"
#include "protocol/message.h"

namespace strata::tactical {

struct LinkOptions {
  std::string host = "127.0.0.1";
  std::uint16_t port = 0;
  std::string client_name = "strata";
  std::chrono::milliseconds connect_timeout{3000};
  std::chrono::milliseconds reply_timeout{3000};  // default for send()
  // After the connection drops: how many times to reconnect (and say hello
  // again) before giving up, and the wait between tries. Requests in flight
  // when it dropped fail; they are never sent twice.
  int reconnect_attempts = 2;
  std::chrono::milliseconds reconnect_delay{200};
  // Sees every line as it is sent (sent = true, when its write starts) and
  // as it arrives (before it is handled), without the newline. For traces
  // and for measuring the link; must be quick and must not call the link.
  std::function<void(bool sent, std::string_view line)> tap;
};

// The reply to one request: ok/done/answer/pong/welcome, or an error whose
// message says what happened (ErrorCode::Timeout, Closed, Protocol: an `err`
// from the vehicle, Io: could not connect).
using ReplyHandler = std::function<void(core::Result<protocol::VehicleMessage>)>;

class VehicleLink : public std::enable_shared_from_this<VehicleLink> {
 public:
  static std::shared_ptr<VehicleLink> create(asio::io_context& io, LinkOptions options);
  ~VehicleLink();

  // Connects and says hello; `done` gets the vehicle's welcome or the reason
  // it could not (refused, timed out, refused as a second client).
  void connect(std::function<void(core::Result<protocol::Welcome>)> done);

  // Sends request (its id is assigned here and returned) and calls handler
  // exactly once: with the reply, or with an error (timeout, link closed).
  protocol::RequestId send(protocol::Request request, ReplyHandler handler,
                           std::optional<std::chrono::milliseconds> timeout = std::nullopt);

  void on_telemetry(std::function<void(const protocol::Telemetry&)> f) { on_telemetry_ = std::move(f); }
  void on_event(std::function<void(const protocol::Event&)> f) { on_event_ = std::move(f); }
  // Called once when the link is gone for good (after the reconnect policy).
  void on_lost(std::function<void(const core::Error&)> f) { on_lost_ = std::move(f); }
  // Lines from the vehicle that could not be decoded (logged by the caller).
  void on_garbage(std::function<void(const std::string&)> f) { on_garbage_ = std::move(f); }

  bool connected() const { return connected_; }
  std::chrono::milliseconds default_timeout() const { return options_.reply_timeout; }
  std::size_t in_flight() const { return pending_.size(); }
  // Closes the socket; pending requests fail with Closed.
  void close();

 private:
  VehicleLink(asio::io_context& io, LinkOptions options);

  struct Pending {
    ReplyHandler handler;
    std::unique_ptr<asio::steady_timer> timer;
    std::string what;  // "exec submerge" for messages
  };

  void start_connect(std::function<void(core::Result<protocol::Welcome>)> done);
  void start_read();
  void handle_line(const protocol::Frame& frame);
  void write(std::string line);
  void start_write();
  void fail_all(const core::Error& error);
  void lost(const std::string& why);
  void try_reconnect(const std::string& why);
  // Ends this connection for good (no reconnect): pending requests fail.
  void abandon(const core::Error& error);
  void complete(protocol::RequestId id, core::Result<protocol::VehicleMessage> result);

  asio::io_context& io_;
  LinkOptions options_;
  asio::ip::tcp::socket socket_;
  asio::steady_timer connect_timer_;
  protocol::LineFramer framer_;
  std::array<char, 4096> read_buffer_{};
  std::deque<std::string> write_queue_;
  bool writing_ = false;
  bool connected_ = false;
  bool closing_ = false;
  int reconnects_left_ = 0;
  protocol::RequestId next_id_ = 1;
  std::map<protocol::RequestId, Pending> pending_;
  std::function<void(const protocol::Telemetry&)> on_telemetry_;
  std::function<void(const protocol::Event&)> on_event_;
  std::function<void(const core::Error&)> on_lost_;
  std::function<void(const std::string&)> on_garbage_;
};

// Describes a request for messages: "exec sleep 1".
std::string describe(const protocol::Request& request);

}  // namespace strata::tactical
