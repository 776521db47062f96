// Capture over loopback TCP: the stream under garbage and damage, and a slow
// processing stage that must not stall reading.
#include <gtest/gtest.h>

#include <condition_variable>
#include <mutex>
#include <random>

#include "sonar/capture.h"
#include "sonar/manager.h"
#include "sonar/test_support.h"

namespace strata::sonar {
namespace {

using testing::options_for;
using testing::PingSynth;
using testing::SynthConfig;
using testing::TestConnection;
using testing::TestServer;

protocol::SonarStatus status(bool on) { return {0.0, on, 0, 0}; }

TEST(FrameQueue, PingsOverTheCapAreDroppedButStatusAndEndAlwaysGetThrough) {
  FrameQueue queue(2);
  EXPECT_TRUE(queue.push({protocol::SonarPing{}}));
  EXPECT_TRUE(queue.push({protocol::SonarPing{}}));
  EXPECT_FALSE(queue.push({protocol::SonarPing{}}));
  EXPECT_TRUE(queue.push({protocol::SonarStatus{}}));
  EXPECT_TRUE(queue.push({protocol::SonarEnd{}}));
  EXPECT_EQ(1u, queue.dropped());
  EXPECT_EQ(4u, queue.peak());
  ASSERT_TRUE(queue.pop(std::chrono::milliseconds(0)));
  EXPECT_TRUE(queue.push({protocol::SonarPing{}}));  // room again
  int items = 0;
  while (queue.pop(std::chrono::milliseconds(0))) ++items;
  EXPECT_EQ(4, items);
  EXPECT_FALSE(queue.pop(std::chrono::milliseconds(10)));
}

TEST(Capture, GarbageBetweenFramesAndADamagedFrameCostOnlyTheDamagedPing) {
  PingSynth synth(SynthConfig{});
  std::mt19937 random(7);
  std::uniform_int_distribution<int> garbage_byte(0, 0x7F);  // never the sync's first byte, 0xA5
  std::string stream = protocol::encode_sonar(status(true));
  std::size_t good_bytes = stream.size();
  const int kPings = 150;
  for (int i = 0; i < kPings; ++i) {
    std::string frame = protocol::encode_sonar(synth.next());
    if (i == 60) {
      frame[frame.size() / 2] = static_cast<char>(frame[frame.size() / 2] ^ 0x40);  // fails its CRC
    } else {
      good_bytes += frame.size();
    }
    if (i % 10 == 3) stream.append(static_cast<std::size_t>(1 + i % 37), static_cast<char>(garbage_byte(random)));
    if (i == 90) stream += protocol::encode_sonar(synth.next()).substr(0, 20);  // a frame cut short
    stream += frame;
  }
  const std::string end = protocol::encode_sonar(protocol::SonarEnd{9.0, 151, 0, "run over"});
  stream += end;
  good_bytes += end.size();

  TestServer server([&](TestConnection& c) {
    // Odd chunk sizes, so frames and garbage straddle reads.
    std::size_t at = 0;
    for (std::size_t chunk = 1; at < stream.size(); chunk = chunk * 7 % 1013 + 1) {
      ASSERT_TRUE(c.send(std::string_view(stream).substr(at, chunk)));
      at += std::min(chunk, stream.size() - at);
    }
  });
  const ManagerSummary s = run_sonar_manager(options_for(server.port(), "garbage"));
  EXPECT_EQ(Outcome::Ended, s.outcome) << s.message;
  EXPECT_EQ(0, s.exit_code);
  EXPECT_EQ(kPings - 1u, s.capture.pings);
  EXPECT_EQ(kPings - 1u, s.processed);
  EXPECT_EQ(2u, s.capture.bad_frames);  // the damaged one and the cut one
  EXPECT_EQ(2u, s.capture.seq_gaps);    // the damaged ping's seq and the cut one's are missing
  EXPECT_EQ(2u, s.capture.lost_pings);
  EXPECT_EQ(stream.size() - good_bytes, s.capture.garbage_bytes);
  EXPECT_EQ(stream.size(), s.capture.bytes);
  EXPECT_EQ(0u, s.capture.queue_drops);
  EXPECT_GE(s.frames, 2u);
}

TEST(Capture, ASlowProcessingStageDoesNotStallReading) {
  // 20 000 pings (about 5 MB) sent while processing is held on its first
  // ping until the server has written them all. Every buffer on the way is
  // small (16 KB to send, 64 KB to receive, 16 KB reads: well under 1 MB in
  // all), so the server can only get there if capture keeps draining the
  // socket while processing stands still.
  const int kPings = 20000;
  PingSynth synth(SynthConfig{});
  std::string pings;
  for (int i = 0; i < kPings; ++i) pings += protocol::encode_sonar(synth.next());

  std::mutex mutex;
  std::condition_variable cv;
  bool all_sent = false;
  bool sends_ok = true;
  double longest_send_s = 0.0;
  TestServer server(
      [&](TestConnection& c) {
        bool ok = c.send(status(true));
        for (std::size_t at = 0; ok && at < pings.size(); at += 4096) {
          ok = c.send(std::string_view(pings).substr(at, 4096));
        }
        {
          std::lock_guard lock(mutex);
          all_sent = true;
          sends_ok = ok;
          longest_send_s = c.longest_send_s();
        }
        cv.notify_all();
        c.send(protocol::SonarEnd{1000.0, kPings, 0, "run over"});
      },
      16 * 1024);

  ManagerOptions o = options_for(server.port(), "slow");
  o.queue_capacity = 64;
  o.capture.socket_buffer_bytes = 64 * 1024;
  o.capture.read_buffer_bytes = 16 * 1024;
  bool held_until_sent = true;
  o.before_ping = [&](const protocol::SonarPing&) {
    std::unique_lock lock(mutex);
    if (!cv.wait_for(lock, std::chrono::seconds(60), [&] { return all_sent; })) held_until_sent = false;
  };
  const ManagerSummary s = run_sonar_manager(o);
  server.join();
  EXPECT_TRUE(held_until_sent) << "the server could not send everything while processing was held";
  EXPECT_TRUE(sends_ok);
  EXPECT_LT(longest_send_s, 5.0);  // a bound far above any send that did not wait for processing
  EXPECT_EQ(Outcome::Ended, s.outcome) << s.message;
  EXPECT_EQ(static_cast<std::uint64_t>(kPings), s.capture.pings);  // every ping read off the socket
  EXPECT_EQ(0u, s.capture.lost_pings);
  EXPECT_GT(s.capture.queue_drops, 0u);  // processing fell behind, and it was counted
  EXPECT_EQ(static_cast<std::uint64_t>(kPings), s.processed + s.capture.queue_drops);
  EXPECT_LE(s.capture.queue_peak, o.queue_capacity + 2);
}

TEST(Capture, StopEndsTheStreamWithStreamClosed) {
  TestServer server([](TestConnection& c) {
    c.send(status(true));
    c.wait_for_close(20.0);
  });
  CaptureOptions o;
  o.port = server.port();
  FrameQueue queue(16);
  Capture capture(o, queue);
  capture.start();
  auto first = queue.pop(std::chrono::seconds(10));
  ASSERT_TRUE(first);
  EXPECT_TRUE(std::holds_alternative<StreamConnected>(first->what));
  auto second = queue.pop(std::chrono::seconds(10));
  ASSERT_TRUE(second);
  EXPECT_TRUE(std::holds_alternative<protocol::SonarStatus>(second->what));
  capture.stop();
  auto last = queue.pop(std::chrono::seconds(10));
  ASSERT_TRUE(last);
  ASSERT_TRUE(std::holds_alternative<StreamClosed>(last->what));
  EXPECT_TRUE(std::get<StreamClosed>(last->what).stopped);
  EXPECT_TRUE(std::get<StreamClosed>(last->what).connected);
}

}  // namespace
}  // namespace strata::sonar
