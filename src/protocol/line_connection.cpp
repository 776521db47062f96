#include "protocol/line_connection.h"

#include <algorithm>
#include <span>
#include <utility>

namespace strata::protocol {

std::string_view why_name(CloseReason::Why why) {
  switch (why) {
    case CloseReason::Why::Open: return "open";
    case CloseReason::Why::Local: return "local";
    case CloseReason::Why::PeerClosed: return "peer_closed";
    case CloseReason::Why::ReadError: return "read_error";
    case CloseReason::Why::WriteError: return "write_error";
    case CloseReason::Why::LineTooLong: return "line_too_long";
    case CloseReason::Why::QueueFull: return "queue_full";
  }
  return "?";
}

std::shared_ptr<LineConnection> LineConnection::create(Socket socket, LineConnectionOptions options,
                                                       Handlers handlers) {
  return std::shared_ptr<LineConnection>(new LineConnection(std::move(socket), options, std::move(handlers)));
}

LineConnection::LineConnection(Socket socket, LineConnectionOptions options, Handlers handlers)
    : socket_(std::move(socket)), options_(options), handlers_(std::move(handlers)), framer_(options.max_line_bytes) {}

LineConnection::~LineConnection() {
  asio::error_code ignored;
  socket_.close(ignored);
}

void LineConnection::start() {
  if (reading_ || closing()) return;
  reading_ = true;
  read();
}

LineConnection::Sent LineConnection::send(std::string bytes) {
  if (closing()) return Sent::Closed;
  if (queued_bytes_ + bytes.size() > options_.max_queue_bytes) {
    if (options_.when_full == LineConnectionOptions::WhenFull::Refuse) return Sent::Refused;
    CloseReason reason{CloseReason::Why::QueueFull,
                       {},
                       "write queue full: " + std::to_string(queued_bytes_) + " bytes waiting, " +
                           std::to_string(bytes.size()) + " more would pass the bound of " +
                           std::to_string(options_.max_queue_bytes)};
    if (shut(std::move(reason))) tell_closed_later();
    return Sent::Closed;
  }
  queued_bytes_ += bytes.size();
  queue_.push_back(std::move(bytes));
  if (!writing_) {
    // Written once the caller's handler is done, with whatever else it
    // queues: a lockstep instant's replies, telemetry and ok go in one
    // system call, not one each.
    writing_ = true;
    asio::post(socket_.get_executor(), [self = shared_from_this()] { self->write_front(); });
  }
  return Sent::Queued;
}

void LineConnection::close(std::string why) {
  owner_closed_ = true;
  shut(CloseReason{CloseReason::Why::Local, {}, std::move(why)});
}

void LineConnection::close_when_written(std::string why) {
  if (closing()) return;
  closing_ = true;
  reason_ = CloseReason{CloseReason::Why::Local, {}, std::move(why)};
  if (!writing_ && shut(reason_)) tell_closed_later();
}

// Told from the io_context: whoever called send() or close_when_written()
// may not expect its own close handler to run inside the call.
void LineConnection::tell_closed_later() {
  asio::post(socket_.get_executor(), [self = shared_from_this()] {
    if (!self->owner_closed_ && self->handlers_.on_close) self->handlers_.on_close(*self, self->reason_);
  });
}

void LineConnection::read() {
  socket_.async_read_some(asio::buffer(buffer_), [self = shared_from_this()](const asio::error_code& e, std::size_t n) {
    if (self->closing()) return;
    if (e) {
      if (e == asio::error::eof) {
        self->fail(CloseReason{CloseReason::Why::PeerClosed, e, "the peer closed the connection"});
      } else {
        self->fail(CloseReason{CloseReason::Why::ReadError, e, "read failed: " + e.message()});
      }
      return;
    }
    for (const auto& frame : self->framer_.feed(std::string_view(self->buffer_.data(), n))) {
      if (frame.too_long && self->options_.overlong == LineConnectionOptions::Overlong::Close) {
        self->fail(CloseReason{CloseReason::Why::LineTooLong,
                               {},
                               "a line over " + std::to_string(self->options_.max_line_bytes) + " bytes"});
        return;
      }
      if (self->handlers_.on_line) self->handlers_.on_line(*self, frame);
      if (self->closing()) return;  // the handler closed it: nothing more is read
    }
    self->read();
  });
}

void LineConnection::write_front() {
  if (closed_ || queue_.empty()) {
    writing_ = false;
    return;
  }
  writing_ = true;
  // Everything queued so far, in one gathered write (deque elements stay
  // where they are while more are queued behind them).
  // The buffers live in the connection, not in a vector made for each write:
  // the write operation copies the span (two words), and gather_ is not
  // touched again until the write completes.
  const std::size_t n = std::min<std::size_t>(queue_.size(), kMaxGather);
  for (std::size_t i = 0; i < n; ++i) gather_[i] = asio::buffer(queue_[i]);
  in_flight_ = n;
  const std::span<const asio::const_buffer> buffers(gather_.data(), n);
  asio::async_write(socket_, buffers, [self = shared_from_this()](const asio::error_code& e, std::size_t) {
    self->writing_ = false;
    if (self->closed_) return;
    for (std::size_t i = 0; i < self->in_flight_; ++i) {
      self->queued_bytes_ -= self->queue_.front().size();
      self->queue_.pop_front();
    }
    self->in_flight_ = 0;
    if (e) {
      self->fail(CloseReason{CloseReason::Why::WriteError, e, "write failed: " + e.message()});
      return;
    }
    if (!self->queue_.empty()) {
      self->write_front();
    } else if (self->closing_) {
      self->fail(self->reason_);
    }
  });
}

bool LineConnection::shut(CloseReason reason) {
  if (closed_) return false;
  closed_ = true;
  reason_ = std::move(reason);
  // A write in progress still points at the ones it took until it is aborted.
  queue_.erase(queue_.begin() + static_cast<std::ptrdiff_t>(std::min(in_flight_, queue_.size())), queue_.end());
  queued_bytes_ = 0;
  asio::error_code ignored;
  socket_.shutdown(asio::socket_base::shutdown_both, ignored);
  socket_.close(ignored);
  return true;
}

void LineConnection::fail(CloseReason reason) {
  if (!shut(std::move(reason))) return;
  if (!owner_closed_ && handlers_.on_close) handlers_.on_close(*this, reason_);
}

}  // namespace strata::protocol
