#include "vehicle/sonar_server.h"

#include <utility>

#include "protocol/line_connection.h"

namespace strata::vehicle {

using asio::ip::tcp;

// A reader: a connection whose lines are ignored (a reader has nothing to
// say; reading notices when it goes away), and a write queue with room for
// max_queue_bytes of pings and some more for the status and end frames, which
// are never dropped. A reader that lets even those pile up is closed.
class SonarServer::Reader {
 public:
  Reader(SonarServer& server, tcp::socket socket) : server_(&server) {
    protocol::LineConnectionOptions o;
    o.overlong = protocol::LineConnectionOptions::Overlong::Deliver;
    o.max_queue_bytes = server.options_.max_queue_bytes + kControlRoomBytes;
    o.when_full = protocol::LineConnectionOptions::WhenFull::Close;
    connection_ = protocol::LineConnection::create(
        std::move(socket), o,
        {[](protocol::LineConnection&, const protocol::Frame&) {},
         [this](protocol::LineConnection&, const protocol::CloseReason&) { leave(); }});
  }

  void start() { connection_->start(); }

  // Queues a frame; a ping (droppable) is dropped when its bound is reached.
  void send(const std::shared_ptr<const std::string>& bytes, bool droppable) {
    if (connection_->closing() || !server_) return;
    if (droppable && connection_->queued_bytes() + bytes->size() > server_->options_.max_queue_bytes) {
      ++dropped_;
      return;
    }
    // A full queue closes the connection; on_close then forgets the reader.
    (void)connection_->send(*bytes);
  }

  // After what is queued: close (and on_close forgets the reader).
  void finish() { connection_->close_when_written("the vehicle is stopping"); }

  // Closes now; the server forgets it.
  void close() {
    connection_->close("the vehicle is stopping");
    leave();
  }

  std::uint64_t dropped() const { return dropped_; }
  void detach() { server_ = nullptr; }
  ~Reader() { connection_->close(); }

 private:
  static constexpr std::size_t kControlRoomBytes = std::size_t{64} * 1024;

  void leave() {
    if (server_) {
      SonarServer* s = std::exchange(server_, nullptr);
      s->remove(this);  // may free this object: touch nothing after
    }
  }
  SonarServer* server_;
  std::shared_ptr<protocol::LineConnection> connection_;
  std::uint64_t dropped_ = 0;
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
    return core::Error{core::ErrorCode::Io, "sonar: cannot listen on " + options_.address + ":" +
                                                std::to_string(options_.port) + ": " + ec.message()};
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
      readers_.erase(it);  // its connection is closed; pending handlers only see that
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
    r->send(std::make_shared<const std::string>(protocol::encode_sonar(
                protocol::SonarStatus{time_s, on, pings_, static_cast<std::uint32_t>(r->dropped())})),
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
