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

TEST_F(StudioServerTest, StreamsPastTheCapAre503AndOtherRequestsAreStillAnswered) {
  std::atomic<bool> stop{false};
  std::vector<std::unique_ptr<StreamReader>> readers;
  const int cap = StudioOptions{}.max_streams;
  for (int i = 0; i < cap; ++i) readers.push_back(std::make_unique<StreamReader>(port_, stop));
  ASSERT_TRUE(wait_for([&] { return hub_.subscribers() == static_cast<std::size_t>(cap); })) << hub_.subscribers();
  // One more: refused at once, with when to come back; no worker held.
  auto more = client().Get("/api/events");
  ASSERT_TRUE(more);
  EXPECT_EQ(503, more->status);
  EXPECT_EQ("5", more->get_header_value("Retry-After"));
  EXPECT_NE(std::string::npos, more->body.find("--max-streams")) << more->body;
  for (int i = 0; i < 5; ++i) {
    auto r = client().Get("/api/primitives");
    ASSERT_TRUE(r) << "request " << i << " got no answer with " << cap << " streams open";
    EXPECT_EQ(200, r->status);
  }
  hub_.publish("report", {{"text", "to all"}});
  for (auto& r : readers) {
    EXPECT_TRUE(wait_for([&] { return r->seen().find("to all") != std::string::npos; }));
  }
  // A stream that ends gives its place back.
  stop = true;
  hub_.publish("report", {{"text", "wake the readers"}});
  for (auto& r : readers) r->thread.join();
  ASSERT_TRUE(wait_for([&] { return hub_.subscribers() == 0; })) << hub_.subscribers();
  std::atomic<bool> stop_again{false};
  StreamReader again(port_, stop_again);
  EXPECT_TRUE(wait_for([&] { return again.seen().find("event: snapshot") != std::string::npos; })) << again.seen();
  // stop() with a stream still open: it ends it and returns.
  server_->stop();
  again.thread.join();
  EXPECT_EQ(0u, hub_.subscribers());
}

// Issue 39: a page on another port held 16 iframes of /api/events, and a
// studio tab in that browser never loaded. A browser says where a request
// comes from; every API request from another site is refused, streams too.
TEST_F(StudioServerTest, CrossSiteRequestsOfEveryMethodAreRefusedStreamsToo) {
  httplib::Client c("127.0.0.1", port_);
  c.set_read_timeout(5, 0);
  for (const char* site : {"same-site", "cross-site"}) {
    for (const char* path : {"/api/events", "/api/files", "/api/mission?path=tank/tank.coral"}) {
      auto r = c.Get(path, {{"Sec-Fetch-Site", site}});
      ASSERT_TRUE(r) << path;
      EXPECT_EQ(403, r->status) << site << " " << path;
      EXPECT_NE(std::string::npos, r->body.find("another site")) << r->body;
    }
    auto w = c.Post("/api/check", {{"Sec-Fetch-Site", site}, {"Origin", origin()}}, R"({"path": "tank/tank.coral"})",
                    "application/json");
    ASSERT_TRUE(w);
    EXPECT_EQ(403, w->status) << site;
  }
  EXPECT_EQ(0u, hub_.subscribers());
  // A GET naming another origin is refused too.
  auto other = c.Get("/api/files", {{"Origin", "http://127.0.0.1:1"}});
  ASSERT_TRUE(other);
  EXPECT_EQ(403, other->status);
  // The page itself, and the address bar, are served.
  for (const char* site : {"same-origin", "none"}) {
    auto r = c.Get("/api/files", {{"Sec-Fetch-Site", site}});
    ASSERT_TRUE(r);
    EXPECT_EQ(200, r->status) << site;
  }
  auto page = c.Get("/", {{"Sec-Fetch-Site", "cross-site"}});  // a link to the studio from elsewhere
  ASSERT_TRUE(page);
  EXPECT_NE(403, page->status);
}

}  // namespace
}  // namespace strata::studio
