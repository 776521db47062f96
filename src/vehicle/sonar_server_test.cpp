#include "vehicle/sonar_server.h"

#include <gtest/gtest.h>

#include <sys/socket.h>

#include <atomic>
#include <chrono>
#include <optional>
#include <thread>
#include <vector>

namespace strata::vehicle {
namespace {

using asio::ip::tcp;
using namespace std::chrono_literals;

protocol::SonarPing ping(std::uint32_t seq) {
  protocol::SonarPing p;
  p.time_s = seq * 0.05;
  p.seq = seq;
  p.bearing_deg = static_cast<float>(seq % 60);
  p.range_m = 10.0f;
  p.bins.assign(200, static_cast<std::uint8_t>(seq & 0xFF));
  return p;
}

// A blocking reader on its own io_context: connects, reads frames.
class TestReader {
 public:
  explicit TestReader(std::uint16_t port) : socket_(io_) {
    socket_.connect({asio::ip::make_address("127.0.0.1"), port});
  }
  // Reads until n frames or end of stream (at most `limit` reads).
  std::vector<protocol::SonarFrame> read(std::size_t n, int limit = 100000) {
    std::vector<protocol::SonarFrame> out;
    char buf[65536];
    while (out.size() < n && limit-- > 0) {
      while (auto f = decoder_.next()) out.push_back(std::move(*f));
      if (out.size() >= n) break;
      asio::error_code ec;
      std::size_t k = socket_.read_some(asio::buffer(buf), ec);
      if (ec) {
        eof_ = true;
        break;
      }
      decoder_.feed(std::string_view(buf, k));
    }
    return out;
  }
  bool eof() const { return eof_; }
  tcp::socket& socket() { return socket_; }

 private:
  asio::io_context io_;
  tcp::socket socket_;
  protocol::SonarDecoder decoder_;
  bool eof_ = false;
};

// Runs the server's io_context until pred() or a bound of handlers / time.
template <typename Pred>
bool run_until(asio::io_context& io, Pred pred) {
  const auto end = std::chrono::steady_clock::now() + 5s;
  while (!pred() && std::chrono::steady_clock::now() < end) {
    io.restart();
    io.run_for(2ms);
  }
  return pred();
}

TEST(SonarServer, AReaderGetsTheStatusThePingsInOrderAndTheEnd) {
  asio::io_context io;
  SonarServer server(io, {});
  ASSERT_TRUE(server.start().ok());
  ASSERT_NE(0, server.port());
  TestReader reader(server.port());
  ASSERT_TRUE(run_until(io, [&] { return server.readers() == 1; }));
  server.status(1.0, true);
  for (std::uint32_t i = 0; i < 50; ++i) server.ping(ping(i));
  server.end(3.5, "the run is over");
  ASSERT_TRUE(run_until(io, [&] { return server.readers() == 0; }));
  auto frames = reader.read(1000);
  ASSERT_EQ(1u + 1u + 50u + 1u, frames.size());
  EXPECT_FALSE(std::get<protocol::SonarStatus>(frames[0]).on);  // on connecting: still off
  EXPECT_TRUE(std::get<protocol::SonarStatus>(frames[1]).on);
  for (std::uint32_t i = 0; i < 50; ++i) EXPECT_EQ(ping(i), std::get<protocol::SonarPing>(frames[2 + i]));
  const auto& end = std::get<protocol::SonarEnd>(frames.back());
  EXPECT_EQ(50u, end.pings_sent);
  EXPECT_EQ(0u, end.pings_dropped);
  EXPECT_EQ("the run is over", end.reason);
  EXPECT_TRUE(reader.eof());
}

TEST(SonarServer, AReaderThatDoesNotReadCostsDroppedPingsNotAStall) {
  asio::io_context io;
  SonarServerOptions o;
  o.max_queue_bytes = 64 * 1024;
  SonarServer server(io, o);
  ASSERT_TRUE(server.start().ok());
  TestReader reader(server.port());
  ASSERT_TRUE(run_until(io, [&] { return server.readers() == 1; }));
  // 20,000 pings (about 5 MB) while the reader reads nothing: the socket
  // buffers fill, then the queue, then pings are dropped for this reader.
  const std::uint32_t n = 20000;
  for (std::uint32_t i = 0; i < n; ++i) {
    server.ping(ping(i));
    io.poll();  // the vehicle's loop goes on: nothing here may block
  }
  EXPECT_GT(server.dropped(), 0u);
  server.end(1000.0, "done");
  // Now the reader reads everything: the pings that came are in order, and
  // with the dropped ones they make up every ping.
  std::vector<protocol::SonarFrame> frames;
  std::thread t([&] { frames = reader.read(n + 10); });
  run_until(io, [&] { return server.readers() == 0; });
  t.join();
  std::uint32_t got = 0, last = 0;
  bool ordered = true;
  for (const auto& f : frames) {
    if (const auto* p = std::get_if<protocol::SonarPing>(&f)) {
      if (got > 0 && p->seq <= last) ordered = false;
      last = p->seq;
      ++got;
    }
  }
  EXPECT_TRUE(ordered);
  ASSERT_TRUE(std::holds_alternative<protocol::SonarEnd>(frames.back()));
  const auto& end = std::get<protocol::SonarEnd>(frames.back());
  EXPECT_EQ(n, end.pings_sent);
  EXPECT_EQ(n, got + end.pings_dropped);
  EXPECT_GT(end.pings_dropped, 0u);
}

TEST(SonarServer, WhatAReaderSendsIsIgnoredAndAReaderThatLeavesIsForgotten) {
  asio::io_context io;
  SonarServer server(io, {});
  ASSERT_TRUE(server.start().ok());
  {
    TestReader reader(server.port());
    ASSERT_TRUE(run_until(io, [&] { return server.readers() == 1; }));
    asio::write(reader.socket(), asio::buffer(std::string("garbage\n\xA5SNR\x01\x01 junk")));
    server.ping(ping(0));
    // Read on a thread while the server's loop runs: its writes complete
    // only there (a blocking read on this thread hung when the status frame's
    // write had not completed before the ping was queued behind it).
    std::atomic<bool> done{false};
    std::vector<protocol::SonarFrame> frames;
    std::thread t([&] {
      frames = reader.read(2);
      done = true;
    });
    if (!run_until(io, [&] { return done.load(); })) ::shutdown(reader.socket().native_handle(), SHUT_RDWR);
    t.join();
    EXPECT_EQ(2u, frames.size());
  }
  ASSERT_TRUE(run_until(io, [&] { return server.readers() == 0; }));
  for (std::uint32_t i = 1; i < 10; ++i) server.ping(ping(i));
  EXPECT_EQ(10u, server.pings());
}

TEST(SonarServer, AfterTheEndNoReaderIsTaken) {
  asio::io_context io;
  SonarServer server(io, {});
  ASSERT_TRUE(server.start().ok());
  const auto port = server.port();
  server.end(0.0, "stopping");
  asio::io_context cio;
  tcp::socket s(cio);
  asio::error_code ec;
  s.connect({asio::ip::make_address("127.0.0.1"), port}, ec);
  EXPECT_TRUE(ec) << "connected after the end";
}

}  // namespace
}  // namespace strata::vehicle
