#include "protocol/line_connection.h"

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace strata::protocol {
namespace {

using asio::ip::tcp;
using namespace std::chrono_literals;
using Why = CloseReason::Why;

// Runs io until pred holds: at most 2 s and 2000 rounds.
template <typename Pred>
bool run_until(asio::io_context& io, Pred pred) {
  const auto end = std::chrono::steady_clock::now() + 2s;
  for (int round = 0; round < 2000 && !pred() && std::chrono::steady_clock::now() < end; ++round) {
    io.restart();
    io.run_for(1ms);
  }
  return pred();
}

// A LineConnection on the accepting end of a loopback connection (a free
// port), and a plain socket as its peer; both on one io_context. The peer
// reads everything that arrives into `received`.
class Loopback {
  // First, so that it is destroyed last: the connection and the sockets must
  // go before the io_context whose services they use.
  asio::io_context io_;

 public:
  explicit Loopback(LineConnectionOptions options = {}) : acceptor_(io_), peer_(io_) {
    acceptor_.open(tcp::v4());
    acceptor_.bind({asio::ip::make_address("127.0.0.1"), 0});
    acceptor_.listen();
    peer_.connect(acceptor_.local_endpoint());
    tcp::socket accepted(io_);
    acceptor_.accept(accepted);
    connection = LineConnection::create(std::move(accepted), options,
                                        {[this](LineConnection&, const Frame& f) {
                                           lines.push_back(f.too_long ? "<too_long:" + f.line + ">" : f.line);
                                         },
                                         [this](LineConnection&, const CloseReason& r) {
                                           ++closes;
                                           reason = r;
                                         }});
    connection->start();
    peer_read();
  }

  // Writes bytes from the peer and runs the loop until they have been read.
  void peer_write(const std::string& bytes) {
    asio::write(peer_, asio::buffer(bytes));
    io_.restart();
    io_.run_for(20ms);
  }

  // Runs the loop a little, for what should not happen.
  void settle() {
    io_.restart();
    io_.run_for(50ms);
  }

  template <typename Pred>
  bool run_until(Pred pred) {
    return strata::protocol::run_until(io_, pred);
  }

  void peer_close() {
    asio::error_code ignored;
    peer_.shutdown(tcp::socket::shutdown_both, ignored);
    peer_.close(ignored);
  }

  std::shared_ptr<LineConnection> connection;
  std::vector<std::string> lines;
  int closes = 0;
  std::optional<CloseReason> reason;
  std::string received;
  bool peer_eof = false;

 private:
  void peer_read() {
    peer_.async_read_some(asio::buffer(buf_), [this](const asio::error_code& e, std::size_t n) {
      if (e) {
        peer_eof = true;
        return;
      }
      received.append(buf_.data(), n);
      peer_read();
    });
  }

  tcp::acceptor acceptor_;
  tcp::socket peer_;
  std::array<char, 4096> buf_{};
};

TEST(LineConnection, PartialLinesAcrossReadsAreJoined) {
  Loopback t;
  t.peer_write("exec 7 sl");
  EXPECT_TRUE(t.lines.empty());
  t.peer_write("eep 1\nask 8 de");
  t.peer_write("pth_reached\r\n\n");
  ASSERT_TRUE(t.run_until([&] { return t.lines.size() == 3; }));
  EXPECT_EQ((std::vector<std::string>{"exec 7 sleep 1", "ask 8 depth_reached", ""}), t.lines);
  EXPECT_FALSE(t.connection->closed());
  EXPECT_EQ(0, t.closes);
}

TEST(LineConnection, AnOverlongLineClosesWithItsReason) {
  LineConnectionOptions o;
  o.max_line_bytes = 16;
  Loopback t(o);
  // 15 bytes and the newline fit; the next line does not, even split.
  t.peer_write("fifteen bytes..\nsixteen bytes...");
  ASSERT_TRUE(t.run_until([&] { return t.closes == 1; }));
  EXPECT_EQ(std::vector<std::string>{"fifteen bytes.."}, t.lines);
  EXPECT_EQ(Why::LineTooLong, t.reason->why);
  EXPECT_EQ("a line over 16 bytes", t.reason->message);
  EXPECT_EQ(Why::LineTooLong, t.connection->close_reason().why);
  EXPECT_TRUE(t.connection->closed());
  ASSERT_TRUE(t.run_until([&] { return t.peer_eof; }));
  EXPECT_EQ(LineConnection::Sent::Closed, t.connection->send("late\n"));
}

TEST(LineConnection, AnOverlongLineCanBeDeliveredInsteadAndReadingGoesOn) {
  LineConnectionOptions o;
  o.max_line_bytes = 8;
  o.overlong = LineConnectionOptions::Overlong::Deliver;
  Loopback t(o);
  t.peer_write("exec 12 far too long\nok 1\n");
  ASSERT_TRUE(t.run_until([&] { return t.lines.size() == 2; }));
  EXPECT_EQ((std::vector<std::string>{"<too_long:exec 12>", "ok 1"}), t.lines);
  EXPECT_FALSE(t.connection->closed());
}

TEST(LineConnection, AFullQueueRefusesWhenAskedToAndStaysOpen) {
  LineConnectionOptions o;
  o.max_queue_bytes = 100;
  o.when_full = LineConnectionOptions::WhenFull::Refuse;
  Loopback t(o);
  const std::string sixty(59, 'a');
  // Nothing is written before the loop runs: the first 60 bytes wait.
  EXPECT_EQ(LineConnection::Sent::Queued, t.connection->send(sixty + "\n"));
  EXPECT_EQ(60u, t.connection->queued_bytes());
  EXPECT_EQ(LineConnection::Sent::Refused, t.connection->send(sixty + "\n"));
  EXPECT_EQ(LineConnection::Sent::Queued, t.connection->send("b\n"));
  ASSERT_TRUE(t.run_until([&] { return t.received.size() == 62; }));
  EXPECT_EQ(sixty + "\nb\n", t.received);
  EXPECT_EQ(0u, t.connection->queued_bytes());
  // Room again once written.
  EXPECT_EQ(LineConnection::Sent::Queued, t.connection->send(sixty + "\n"));
  EXPECT_FALSE(t.connection->closed());
  EXPECT_EQ(0, t.closes);
}

TEST(LineConnection, AFullQueueClosesWithItsReasonByDefault) {
  LineConnectionOptions o;
  o.max_queue_bytes = 100;
  Loopback t(o);
  EXPECT_EQ(LineConnection::Sent::Queued, t.connection->send(std::string(59, 'a') + "\n"));
  EXPECT_EQ(LineConnection::Sent::Closed, t.connection->send(std::string(59, 'b') + "\n"));
  EXPECT_TRUE(t.connection->closed());
  EXPECT_EQ(0, t.closes) << "told from the loop, not inside send()";
  ASSERT_TRUE(t.run_until([&] { return t.closes == 1 && t.peer_eof; }));
  EXPECT_EQ(Why::QueueFull, t.reason->why);
  EXPECT_EQ("write queue full: 60 bytes waiting, 60 more would pass the bound of 100", t.reason->message);
  EXPECT_EQ(LineConnection::Sent::Closed, t.connection->send("c\n"));
}

TEST(LineConnection, ThePeerClosingIsReportedOnce) {
  Loopback t;
  t.peer_write("bye 3\n");
  t.peer_close();
  ASSERT_TRUE(t.run_until([&] { return t.closes == 1; }));
  EXPECT_EQ(std::vector<std::string>{"bye 3"}, t.lines);
  EXPECT_EQ(Why::PeerClosed, t.reason->why);
  EXPECT_EQ("the peer closed the connection", t.reason->message);
  t.settle();
  EXPECT_EQ(1, t.closes);
}

// One write gathers at most 64 queued pieces, and a large burst is written
// in parts: every byte still arrives, in order, burst after burst.
TEST(LineConnection, BurstsLargerThanOneGatheredWriteArriveWholeAndInOrder) {
  LineConnectionOptions o;
  o.max_queue_bytes = std::size_t{8} << 20;
  Loopback t(o);
  std::string expected;
  for (int burst = 0; burst < 2; ++burst) {
    for (int i = 0; i < 300; ++i) {
      std::string line = "tlm " + std::to_string(burst) + " " + std::to_string(i) + " " +
                         std::string(static_cast<std::size_t>(i % 7) * 900, static_cast<char>('a' + i % 26)) + "\n";
      expected += line;
      ASSERT_EQ(LineConnection::Sent::Queued, t.connection->send(std::move(line)));
    }
    // Written (the queue empty) and read (every byte at the peer).
    ASSERT_TRUE(t.run_until([&] { return t.connection->queued_bytes() == 0 && t.received.size() >= expected.size(); }));
  }
  EXPECT_EQ(expected, t.received);
  EXPECT_FALSE(t.connection->closing());
}

TEST(LineConnection, CloseWhenWrittenWritesEverythingThenClosesAndSaysSo) {
  Loopback t;
  EXPECT_EQ(LineConnection::Sent::Queued, t.connection->send("ok 1\n"));
  EXPECT_EQ(LineConnection::Sent::Queued, t.connection->send("err 0 busy one client at a time\n"));
  t.connection->close_when_written("refused");
  EXPECT_TRUE(t.connection->closing());
  EXPECT_EQ(LineConnection::Sent::Closed, t.connection->send("late\n"));
  t.peer_write("ping 4\n");
  ASSERT_TRUE(t.run_until([&] { return t.peer_eof && t.closes == 1; }));
  EXPECT_EQ("ok 1\nerr 0 busy one client at a time\n", t.received);
  EXPECT_TRUE(t.lines.empty()) << "nothing is read after close_when_written";
  EXPECT_TRUE(t.connection->closed());
  EXPECT_EQ(Why::Local, t.reason->why);
  EXPECT_EQ("refused", t.reason->message);
}

TEST(LineConnection, CloseWhenWrittenWithNothingQueuedClosesAndSaysSoFromTheLoop) {
  Loopback t;
  t.connection->close_when_written("done");
  EXPECT_TRUE(t.connection->closed());
  EXPECT_EQ(0, t.closes);
  ASSERT_TRUE(t.run_until([&] { return t.peer_eof && t.closes == 1; }));
  EXPECT_EQ("done", t.reason->message);
}

TEST(LineConnection, CloseDropsTheQueueAndCallsNothingMore) {
  Loopback t;
  EXPECT_EQ(LineConnection::Sent::Queued, t.connection->send("ok 1\n"));
  t.connection->close("stopping");
  EXPECT_EQ(0u, t.connection->queued_bytes());
  t.peer_write("ping 5\n");
  ASSERT_TRUE(t.run_until([&] { return t.peer_eof; }));
  EXPECT_TRUE(t.lines.empty());
  EXPECT_EQ(0, t.closes);
  EXPECT_EQ("stopping", t.connection->close_reason().message);
}

}  // namespace
}  // namespace strata::protocol
