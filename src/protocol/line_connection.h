#pragma once
// One TCP connection that reads lines and writes bytes, over Asio: the one
// socket every Strata peer uses (the vehicle's control server, the Tactical
// level's link to it, the vehicle's sonar socket).
//
// Reading: bytes are cut into lines by a LineFramer; each complete line goes
// to on_line, in order, without its "\n" or "\r\n". A partial line waits for
// the rest across reads. A line over max_line_bytes (terminator included)
// either closes the connection (Overlong::Close, reason LineTooLong) or is
// handed to on_line once as a Frame with too_long set, its first bytes kept,
// and the rest of it dropped (Overlong::Deliver: for a protocol that answers
// `err ID too_long`).
//
// Writing: send() queues bytes (a whole line with its "\n", or a binary
// frame) and writes them in order. The queue is bounded in bytes: a send that
// would take it past max_queue_bytes is refused (WhenFull::Refuse: nothing
// queued, the connection stays open, send returns Sent::Refused) or closes
// the connection (WhenFull::Close, reason QueueFull; send returns
// Sent::Closed). A send on a closed or closing connection returns
// Sent::Closed and queues nothing. What is queued is written once the
// handler that queued it is done, everything queued by then in one gathered
// write (up to 64 pieces), so a burst of lines costs one system call.
//
// Closing: any error closes the socket (both directions) at once, and the
// connection stays closed; close_reason() says why. on_close is called once,
// from the io_context (never from inside a call to this class), whenever the
// connection closes except by the owner's close(): the peer closed
// (PeerClosed), a read or write failed (ReadError, WriteError), an overlong
// line, a full queue, or what close_when_written() asked for is done (Local;
// WriteError if the last writes failed). After close() no handler is called
// again, so the owner may be destroyed once it has closed its connections.
//
// Threads: one. Every method must be called on the io_context's thread, and
// the handlers run there. The connection keeps itself alive while it has
// operations pending.
#include <array>
#include <cstddef>
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

#include <asio.hpp>

#include "protocol/framer.h"
#include "protocol/message.h"

namespace strata::protocol {

struct CloseReason {
  enum class Why {
    Open,         // not closed yet
    Local,        // the owner's close() or close_when_written()
    PeerClosed,   // the peer ended the stream
    ReadError,    // a read failed (error says how)
    WriteError,   // a write failed (error says how)
    LineTooLong,  // a line over max_line_bytes with Overlong::Close
    QueueFull,    // a send past max_queue_bytes with WhenFull::Close
  };
  Why why = Why::Open;
  asio::error_code error;  // ReadError, WriteError
  std::string message;     // for people: "the peer closed the connection", ...
};

std::string_view why_name(CloseReason::Why why);

struct LineConnectionOptions {
  enum class Overlong { Close, Deliver };
  enum class WhenFull { Refuse, Close };
  // The longest line taken, its "\n" included (at least 2).
  std::size_t max_line_bytes = kMaxLineBytes;
  Overlong overlong = Overlong::Close;
  // Bytes queued and not yet written (the one being written included).
  std::size_t max_queue_bytes = 1u << 20;
  WhenFull when_full = WhenFull::Close;
};

class LineConnection : public std::enable_shared_from_this<LineConnection> {
 public:
  enum class Sent { Queued, Refused, Closed };

  struct Handlers {
    std::function<void(LineConnection& c, const Frame& line)> on_line;
    std::function<void(LineConnection& c, const CloseReason& reason)> on_close;
  };

  // A connected stream socket: TCP, or one end of a pair of local sockets
  // (an embedded vehicle; a tcp::socket converts to it).
  using Socket = asio::generic::stream_protocol::socket;

  // Takes a connected socket. Nothing is read until start().
  static std::shared_ptr<LineConnection> create(Socket socket, LineConnectionOptions options, Handlers handlers);
  ~LineConnection();
  LineConnection(const LineConnection&) = delete;
  LineConnection& operator=(const LineConnection&) = delete;

  // Starts reading.
  void start();
  Sent send(std::string bytes);
  // Closes now; what is queued is dropped, and no handler is called again.
  // Idempotent. close_reason().why is Local unless it had closed already.
  void close(std::string why = "closed by this end");
  // Stops reading (no line is delivered after this call returns) and closes
  // once everything queued is written; on_close says when.
  void close_when_written(std::string why = "closed by this end");

  bool closed() const { return closed_; }
  bool closing() const { return closing_ || closed_; }
  const CloseReason& close_reason() const { return reason_; }
  std::size_t queued_bytes() const { return queued_bytes_; }
  const LineConnectionOptions& options() const { return options_; }

 private:
  LineConnection(Socket socket, LineConnectionOptions options, Handlers handlers);
  void read();
  void write_front();
  // Closes the socket and records why; returns false if already closed.
  bool shut(CloseReason reason);
  // Closes for a reason of its own or the peer's and tells on_close.
  void fail(CloseReason reason);
  void tell_closed_later();

  Socket socket_;
  LineConnectionOptions options_;
  Handlers handlers_;
  LineFramer framer_;
  std::array<char, 4096> buffer_{};
  std::deque<std::string> queue_;
  std::size_t queued_bytes_ = 0;
  std::size_t in_flight_ = 0;                            // the first in_flight_ of queue_ are being written
  static constexpr std::size_t kMaxGather = 64;          // at most this many in one write
  std::array<asio::const_buffer, kMaxGather> gather_{};  // the write in progress's pieces
  bool writing_ = false;                                 // a write is under way or posted
  bool reading_ = false;
  bool closing_ = false;
  bool closed_ = false;
  bool owner_closed_ = false;  // close(): no handler is called again
  CloseReason reason_;
};

}  // namespace strata::protocol
