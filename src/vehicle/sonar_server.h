#pragma once
// The vehicle's sonar socket (docs/protocol.md, "Sonar stream"): a second
// TCP listener on which the sonar's pings go out, as soon as they are
// acquired, to every reader connected (the Sonar Manager), in the binary
// frames of protocol/sonar_frame.h.
//
// Never in the way of the control link: it runs on the vehicle's io_context
// and only ever writes asynchronously. Each reader has a queue bounded in
// bytes; a ping that does not fit is dropped for that reader and counted (its
// seq gap shows where), so a slow or stuck reader costs memory up to the
// bound and nothing else. A reader gets a SonarStatus when it connects and
// whenever the sonar starts or stops, and a SonarEnd when the vehicle stops,
// after which its socket is closed once what was queued is written.
//
// Threads: one; everything runs on the io_context given. Destroy the server
// before the io_context runs again without it.
#include <cstddef>
#include <cstdint>
#include <list>
#include <memory>
#include <string>

#include <asio.hpp>

#include "core/result.h"
#include "protocol/sonar_frame.h"

namespace strata::vehicle {

struct SonarServerOptions {
  std::string address = "127.0.0.1";
  std::uint16_t port = 0;                  // 0: a free port
  std::size_t max_queue_bytes = 1u << 20;  // per reader; a ping past it is dropped
  std::size_t max_readers = 8;             // more are refused (closed at once)
};

class SonarServer {
 public:
  SonarServer(asio::io_context& io, SonarServerOptions options);
  ~SonarServer();
  SonarServer(const SonarServer&) = delete;
  SonarServer& operator=(const SonarServer&) = delete;

  // Binds and listens; ErrorCode::Io if the address is taken.
  core::Result<void> start();
  std::uint16_t port() const { return port_; }

  // The sonar started or stopped at sim time t: every reader is told.
  void status(double time_s, bool on);
  // One ping, to every reader with room for it.
  void ping(const protocol::SonarPing& ping);
  // The vehicle is stopping: readers get a SonarEnd and are closed once their
  // queue is written; no new reader is taken. Idempotent.
  void end(double time_s, const std::string& reason);
  // Closes every socket now, without an end frame.
  void stop();

  std::size_t readers() const { return readers_.size(); }
  std::uint32_t pings() const { return pings_; }  // pings offered
  // Pings dropped for a slow reader, summed over readers (current and gone).
  std::uint64_t dropped() const;

 private:
  class Reader;
  void accept();
  void remove(Reader* r);

  asio::io_context& io_;
  SonarServerOptions options_;
  asio::ip::tcp::acceptor acceptor_;
  std::list<std::shared_ptr<Reader>> readers_;
  std::uint16_t port_ = 0;
  bool on_ = false;
  bool ended_ = false;
  double last_time_s_ = 0.0;
  std::uint32_t pings_ = 0;
  std::uint64_t dropped_gone_ = 0;  // by readers that have left
};

}  // namespace strata::vehicle
