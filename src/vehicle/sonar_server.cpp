#include "vehicle/sonar_server.h"

#include <deque>

namespace strata::vehicle {

using asio::ip::tcp;

class SonarServer::Reader : public std::enable_shared_from_this<Reader> {
 public:
  Reader(SonarServer& server, tcp::socket socket) : server_(&server), socket_(std::move(socket)) {}

  void start() { read(); }

  // Queues a frame; a ping (droppable) is dropped when the queue is full.
  void send(std::shared_ptr<const std::string> bytes, bool droppable) {
    if (closing_ || !server_) return;
    if (droppable && queued_bytes_ + bytes->size() > server_->options_.max_queue_bytes) {
      ++dropped_;
      return;
    }
    queued_bytes_ += bytes->size();
    queue_.push_back(std::move(bytes));
    if (!writing_) write();
  }

  // After what is queued: close.
  void finish() {
    closing_ = true;
    if (!writing_) close();
  }

  void close() {
    asio::error_code ignored;
    socket_.shutdown(tcp::socket::shutdown_both, ignored);
    socket_.close(ignored);
    if (server_) {
      SonarServer* s = std::exchange(server_, nullptr);
      s->remove(this);  // may free this object: touch nothing after
    }
  }

  std::uint64_t dropped() const { return dropped_; }
  void detach() { server_ = nullptr; }

 private:
  void write() {
    writing_ = true;
    asio::async_write(socket_, asio::buffer(*queue_.front()),
                      [self = shared_from_this()](const asio::error_code& ec, std::size_t) {
                        self->writing_ = false;
                        if (!self->server_) return;
                        if (ec) {
                          self->close();
                          return;
                        }
                        self->queued_bytes_ -= self->queue_.front()->size();
                        self->queue_.pop_front();
                        if (!self->queue_.empty()) {
                          self->write();
                        } else if (self->closing_) {
                          self->close();
                        }
                      });
  }

  // A reader has nothing to say; reading notices when it goes away.
  void read() {
    socket_.async_read_some(asio::buffer(scratch_), [self = shared_from_this()](const asio::error_code& ec, std::size_t) {
      if (!self->server_) return;
      if (ec) {
        if (!self->writing_) self->close();
        return;
      }
      self->read();
    });
  }

  SonarServer* server_;
  tcp::socket socket_;
  std::deque<std::shared_ptr<const std::string>> queue_;
  std::size_t queued_bytes_ = 0;
  std::uint64_t dropped_ = 0;
  bool writing_ = false;
  bool closing_ = false;
  char scratch_[256];
};

SonarServer::SonarServer(asio::io_context& io, SonarServerOptions options)
    : io_(io), options_(std::move(options)), acceptor_(io) {}

SonarServer::~SonarServer() { stop(); }

core::Result<void> SonarServer::start() {
  asio::error_code ec;
  auto address = asio::ip::make_address(options_.address, ec);
  if (ec) return core::Error{core::ErrorCode::InvalidInput, "sonar: bad address '" + options_.address + "'"};
  tcp::endpoint endpoint(address, options_.port);
  acceptor_.open(endpoint.protocol(), ec);
  if (!ec) acceptor_.set_option(tcp::acceptor::reuse_address(true), ec);
  if (!ec) acceptor_.bind(endpoint, ec);
  if (!ec) acceptor_.listen(asio::socket_base::max_listen_connections, ec);
  if (ec) {
    return core::Error{core::ErrorCode::Io,
                       "sonar: cannot listen on " + options_.address + ":" + std::to_string(options_.port) + ": " +
                           ec.message()};
  }
  port_ = acceptor_.local_endpoint().port();
  accept();
  return {};
}

void SonarServer::accept() {
  acceptor_.async_accept([this](const asio::error_code& ec, tcp::socket socket) {
    if (ec) return;  // closed
    if (ended_ || readers_.size() >= options_.max_readers) {
      asio::error_code ignored;
      socket.close(ignored);
    } else {
      asio::error_code ignored;
      socket.set_option(tcp::no_delay(true), ignored);
      auto r = std::make_shared<Reader>(*this, std::move(socket));
      readers_.push_back(r);
      r->start();
      r->send(std::make_shared<const std::string>(
                  protocol::encode_sonar(protocol::SonarStatus{last_time_s_, on_, pings_, 0})),
              false);
    }
    accept();
  });
}

void SonarServer::remove(Reader* r) {
  for (auto it = readers_.begin(); it != readers_.end(); ++it) {
    if (it->get() == r) {
      dropped_gone_ += r->dropped();
      readers_.erase(it);  // the pending handlers keep it alive until they run
      return;
    }
  }
}

void SonarServer::status(double time_s, bool on) {
  on_ = on;
  last_time_s_ = time_s;
  // A copy: a reader that fails while being sent to leaves the list.
  auto readers = readers_;
  for (auto& r : readers) {
    r->send(std::make_shared<const std::string>(
                protocol::encode_sonar(protocol::SonarStatus{time_s, on, pings_, static_cast<std::uint32_t>(r->dropped())})),
            false);
  }
}

void SonarServer::ping(const protocol::SonarPing& ping) {
  ++pings_;
  last_time_s_ = ping.time_s;
  if (readers_.empty()) return;
  auto bytes = std::make_shared<const std::string>(protocol::encode_sonar(ping));
  auto readers = readers_;
  for (auto& r : readers) r->send(bytes, true);
}

void SonarServer::end(double time_s, const std::string& reason) {
  if (ended_) return;
  ended_ = true;
  asio::error_code ignored;
  acceptor_.close(ignored);
  auto readers = readers_;
  for (auto& r : readers) {
    r->send(std::make_shared<const std::string>(protocol::encode_sonar(
                protocol::SonarEnd{time_s, pings_, static_cast<std::uint32_t>(r->dropped()), reason})),
            false);
    r->finish();
  }
}

void SonarServer::stop() {
  ended_ = true;
  asio::error_code ignored;
  acceptor_.close(ignored);
  auto readers = std::move(readers_);
  readers_.clear();
  for (auto& r : readers) {
    dropped_gone_ += r->dropped();
    r->detach();
    r->close();
  }
}

std::uint64_t SonarServer::dropped() const {
  std::uint64_t n = dropped_gone_;
  for (const auto& r : readers_) n += r->dropped();
  return n;
}

}  // namespace strata::vehicle
