// The studio's event stream (/api/events): snapshot first, then events;
// clients that leave or stay do not wedge the server.
#include <atomic>
#include <chrono>
#include <functional>
#include <thread>

#include "studio/server.h"
#include "studio/server_test_support.h"

namespace strata::studio {
namespace {

// Reads one event stream on its own thread until told to stop.
struct StreamReader {
  explicit StreamReader(std::uint16_t port, std::atomic<bool>& stop) {
    thread = std::thread([this, port, &stop] {
      httplib::Client c("127.0.0.1", port);
      c.set_read_timeout(10, 0);
      c.Get("/api/events", [&](const char* data, std::size_t n) {
        std::lock_guard lock(mutex);
        text.append(data, n);
        return !stop.load();
      });
    });
  }
  ~StreamReader() {
    if (thread.joinable()) thread.join();
  }
  std::string seen() {
    std::lock_guard lock(mutex);
    return text;
  }
  std::thread thread;
  std::mutex mutex;
  std::string text;
};

bool wait_for(const std::function<bool()>& done, std::chrono::milliseconds bound = 5000ms) {
  for (auto end = std::chrono::steady_clock::now() + bound; std::chrono::steady_clock::now() < end;) {
    if (done()) return true;
    std::this_thread::sleep_for(10ms);
  }
  return done();
}

TEST_F(StudioServerTest, AStreamGetsTheSnapshotThenEvents) {
  std::atomic<bool> stop{false};
  StreamReader reader(port_, stop);
  ASSERT_TRUE(wait_for([&] { return reader.seen().find("event: snapshot") != std::string::npos; })) << reader.seen();
  hub_.publish("report", {{"t", 1.0}, {"text", "hello there"}});
  EXPECT_TRUE(wait_for([&] { return reader.seen().find("hello there") != std::string::npos; })) << reader.seen();
  EXPECT_TRUE(wait_for([&] { return reader.seen().find(": ping") != std::string::npos; }));
  stop = true;
}

TEST_F(StudioServerTest, AClientLeavingMidStreamDoesNotWedgeTheServer) {
  {
    std::atomic<bool> stop{false};
    StreamReader reader(port_, stop);
    ASSERT_TRUE(wait_for([&] { return hub_.subscribers() == 1; }));
    stop = true;
    hub_.publish("report", {{"text", "wake the reader"}});
  }
  // The server notices on its next write (a heartbeat at the latest).
  EXPECT_TRUE(wait_for([&] { return hub_.subscribers() == 0; })) << hub_.subscribers();
  auto r = client().Get("/api/files");
  ASSERT_TRUE(r);
  EXPECT_EQ(200, r->status);
}

TEST_F(StudioServerTest, TwentyOpenStreamsDoNotBlockOtherRequestsAndStopReturns) {
  std::atomic<bool> stop{false};
  std::vector<std::unique_ptr<StreamReader>> readers;
  for (int i = 0; i < 20; ++i) readers.push_back(std::make_unique<StreamReader>(port_, stop));
  ASSERT_TRUE(wait_for([&] { return hub_.subscribers() == 20; })) << hub_.subscribers();
  for (int i = 0; i < 5; ++i) {
    auto r = client().Get("/api/primitives");
    ASSERT_TRUE(r) << "request " << i << " got no answer with 20 streams open";
    EXPECT_EQ(200, r->status);
  }
  hub_.publish("report", {{"text", "to all"}});
  for (auto& r : readers) {
    EXPECT_TRUE(wait_for([&] { return r->seen().find("to all") != std::string::npos; }));
  }
  // stop() with the streams still open: it ends them and returns.
  server_->stop();
  for (auto& r : readers) r->thread.join();
  EXPECT_EQ(0u, hub_.subscribers());
}

}  // namespace
}  // namespace strata::studio
