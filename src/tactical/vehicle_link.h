#pragma once
// The Tactical level's end of the link to the Execution level: one TCP
// connection, non-blocking on an Asio io_context (one thread), speaking
// protocol 2 (or 1, if asked). Several requests may be in flight; each has
// its own reply timeout (wall time: in lockstep the vehicle answers in
// microseconds, so a silent vehicle is a lost link, not a slow one).
//
// Lockstep barrier (the welcome says lockstep and version 2): the vehicle
// moves simulated time only on `advance` (docs/protocol.md §8), and the link
// sends it by itself once the caller is quiescent: exec/ask/ood requests are
// in flight, no advance is outstanding, no Hold is alive, and nothing has
// happened on the link since the check was posted to the io_context (so it
// runs after the handlers that issued calls, and after the work they posted
// before it). Replies to exec/ask/ood are handed to their handlers together,
// in arrival order, when the advance's `ok` arrives (the vehicle's end of
// that instant), never one by one as TCP happens to split the bytes.
//   Simulated-time timeouts (lockstep, with a vehicle whose welcome tells
// its time, which is how it says it takes a bounded advance): a request sent with a simulated timeout S at time t must
// be answered by t + S. Each advance names the earliest such deadline
// (`advance ID UNTIL_S`); the vehicle moves time no further and answers with
// its time (`ok ID T`); requests whose deadline has come by T then fail with
// ErrorCode::Timeout, in id order. A lost link still carries that clock
// (docs/protocol.md §8), so a silent vehicle costs simulated seconds, not
// wall seconds, and the run stays a pure function of its inputs. The
// wall-clock timeout stays, for a vehicle that does not answer at all, but
// is then at least LinkOptions::stall_timeout (a minute). So the
// calls made in response to one instant's replies all go before the next
// advance, and a run stays a pure function of its inputs. Callers see one
// call in flight at a time behave exactly as in protocol 1.
//   Whoever posts work to the io_context that may issue calls through this
// link (TacticalLevel posts REPORT's completion, and local errors) must take
// a Hold before posting and let it go once that work has run.
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

#include <deque>

#include <asio.hpp>

#include "core/result.h"
#include "protocol/codec.h"
#include "protocol/line_connection.h"
#include "protocol/message.h"
#include "tactical/execution_link.h"

namespace strata::tactical {

struct LinkOptions {
  std::string host = "127.0.0.1";
  std::uint16_t port = 0;
  std::string client_name = "strata";
  std::chrono::milliseconds connect_timeout{3000};
  std::chrono::milliseconds reply_timeout{3000};  // default for send()
  // With simulated-time deadlines (lockstep, a bounded advance), those
  // decide when a call times out; the wall clock only catches a vehicle that
  // stopped answering altogether, after at least this long, so that no
  // machine's load can decide a lockstep run.
  std::chrono::milliseconds stall_timeout{60000};
  // After the connection drops: how many times to reconnect (and say hello
  // again) before giving up, and the wait between tries. Requests in flight
  // when it dropped fail; they are never sent twice.
  int reconnect_attempts = 2;
  std::chrono::milliseconds reconnect_delay{200};
  // The protocol version said in hello: 2 (the newest), or 1 for version 1's
  // lockstep, where each request moves the vehicle's time by itself and
  // requests in flight together are served one after the other.
  int protocol_version = protocol::kProtocolVersion;
  // Sees every line as it is sent (sent = true, when its write starts) and
  // as it arrives (before it is handled), without the newline. For traces
  // and for measuring the link; must be quick and must not call the link.
  std::function<void(bool sent, std::string_view line)> tap;
};

class VehicleLink final : public ExecutionLink {
 public:
  using Hold = ExecutionLink::Hold;

  static std::shared_ptr<VehicleLink> create(asio::io_context& io, LinkOptions options);
  ~VehicleLink() override;

  // Connects and says hello; `done` gets the vehicle's welcome or the reason
  // it could not (refused, timed out, refused as a second client).
  void connect(const std::function<void(core::Result<protocol::Welcome>)>& done);
  // The same over one end of a connected pair of local sockets, the other
  // end an embedded vehicle's (VehicleServer::start_paired): no host, no
  // port, and no reconnecting when it closes.
  void connect_paired(protocol::LineConnection::Socket socket,
                      std::function<void(core::Result<protocol::Welcome>)> done);

  // Sends request (its id is assigned here and returned) and calls handler
  // exactly once: with the reply, or with an error (timeout, link closed).
  // sim_timeout_s: the simulated-time timeout (lockstep, above); without it
  // only the wall-clock one applies.
  protocol::RequestId send(protocol::Request request, ReplyHandler handler,
                           std::optional<std::chrono::milliseconds> timeout = std::nullopt,
                           std::optional<double> sim_timeout_s = std::nullopt) override;

  bool connected() const override { return connected_; }
  // The session's protocol version (the welcome's), 0 before one.
  int session_version() const { return session_version_; }
  // Whether the link sends `advance` (lockstep, protocol 2).
  bool lockstep_barrier() const { return barrier_; }
  // How many advances this link has sent, for tests and traces.
  std::uint64_t advances_sent() const { return advances_sent_; }
  std::chrono::milliseconds default_timeout() const override { return options_.reply_timeout; }
  std::size_t in_flight() const { return pending_.size(); }
  // The vehicle's simulated time as far as the link knows it (the welcome's,
  // then every reply's and advance's); nullopt before the vehicle told it.
  std::optional<double> sim_time_s() const override { return sim_now_; }
  // Closes the socket; pending requests fail with Closed.
  void close() override;

 private:
  void hold_released() override { note_activity(); }
  std::shared_ptr<VehicleLink> self() { return std::static_pointer_cast<VehicleLink>(shared_from_this()); }
  VehicleLink(asio::io_context& io, LinkOptions options);

  struct Pending {
    ReplyHandler handler;
    std::unique_ptr<asio::steady_timer> timer;
    std::string what;    // "exec submerge" for messages
    bool timed = false;  // exec/ask/ood: needs simulated time, so an advance
    std::chrono::milliseconds wait{0};
    std::optional<double> sim_deadline_s;  // lockstep: answered by then, or timed out
    double sim_timeout_s = 0;
  };

  void start_connect(const std::function<void(core::Result<protocol::Welcome>)>& done);
  // Connected: the line connection made and hello sent; done once answered.
  // The connect timer: when it fires before `finished`, the link is
  // abandoned and done told "no answer from VEHICLE within N ms".
  std::shared_ptr<bool> arm_connect_timer(const std::string& vehicle,
                                          const std::function<void(core::Result<protocol::Welcome>)>& done);
  void say_hello(protocol::LineConnection::Socket socket, const std::shared_ptr<bool>& finished,
                 std::function<void(core::Result<protocol::Welcome>)> done);
  void handle_line(const protocol::Frame& frame);
  void write(std::string line);
  void connection_closed(protocol::LineConnection& c, const protocol::CloseReason& why);
  // Closes the connection (or the connect in progress) without a word.
  void drop_connection(const std::string& why);
  void fail_all(const core::Error& error);
  void lost(const std::string& why);
  void try_reconnect(const std::string& why);
  // Ends this connection for good (no reconnect): pending requests fail.
  void abandon(const core::Error& error);
  void complete(protocol::RequestId id, core::Result<protocol::VehicleMessage> result);
  // A reply (or error) from the vehicle for request id: to its handler now,
  // or, for exec/ask/ood under the barrier, when the advance ends.
  void deliver(protocol::RequestId id, core::Result<protocol::VehicleMessage> result);
  // Something happened that may let (or need) an advance go: posts a check.
  void note_activity();
  void maybe_advance(std::uint64_t generation);
  // The outstanding advance is over (its ok, an error, or its timeout): the
  // replies held for it go to their handlers, then, if the vehicle said its
  // time, the requests whose simulated deadline has come time out.
  void finish_advance(std::optional<double> sim_time_s = std::nullopt);
  void saw_time(double sim_time_s);
  void end_session();
  asio::io_context& io_;
  LinkOptions options_;
  asio::ip::tcp::socket socket_;  // while connecting
  asio::steady_timer connect_timer_;
  std::shared_ptr<protocol::LineConnection> connection_;  // once connected
  bool connected_ = false;
  bool closing_ = false;
  int reconnects_left_ = 0;
  protocol::RequestId next_id_ = 1;
  std::map<protocol::RequestId, Pending> pending_;
  int session_version_ = 0;
  bool barrier_ = false;
  std::optional<protocol::RequestId> advance_id_;
  std::optional<double> sim_now_;
  bool bounded_ = false;  // the vehicle takes `advance ID UNTIL_S` (its welcome said time=)
  asio::steady_timer advance_timer_;
  std::deque<std::pair<protocol::RequestId, core::Result<protocol::VehicleMessage>>> held_;
  std::uint64_t activity_ = 0;  // generation of the newest quiescence check
  std::uint64_t advances_sent_ = 0;
};

// Describes a request for messages: "exec sleep 1".
std::string describe(const protocol::Request& request);
// "vehicle refused `exec fly` (request 3): unknown_function: MESSAGE": an
// `err` reply to the request described as `what`, for people and the log.
std::string refusal_text(std::string_view what, const protocol::Err& err);

}  // namespace strata::tactical
