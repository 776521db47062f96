// The studio server's limits over loopback (docs/studio.md, "Host and
// Origin", "Other sites", "Limits"): bounded and framed bodies, the Host
// named once, foreign hosts and origins, headers, and the slots that bound
// verifications and event streams. Requests the client library would not
// send go out raw.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <filesystem>
#include <future>
#include <string>
#include <vector>

#include "studio/server.h"
#include "studio/server_test_support.h"

namespace strata::studio {
namespace {
TEST_F(StudioServerTest, BodiesAreBounded) {
  auto c = client();
  std::string big(5u << 20, 'x');
  auto r = c.Put("/api/file?path=tank/big.coral", big, "text/plain");
  ASSERT_TRUE(r);
  EXPECT_EQ(413, r->status);
  EXPECT_FALSE(fs::exists(base_ / "root/tank/big.coral"));
}

// What one raw request gets back (its status line and the rest), sent as
// written: framings and headers the client library would not send.
std::string raw_request(std::uint16_t port, const std::string& text) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(port);
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (fd < 0 || ::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) return "";
  timeval tv{10, 0};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  ::send(fd, text.data(), text.size(), MSG_NOSIGNAL);
  std::string got;
  char buf[4096];
  for (ssize_t n; (n = ::recv(fd, buf, sizeof buf, 0)) > 0;) {
    got.append(buf, static_cast<std::size_t>(n));
    if (got.find("\r\n\r\n") != std::string::npos && got.find('}') != std::string::npos) break;
  }
  ::close(fd);
  return got;
}

// Issue 39: `Transfer-Encoding: chunked` skipped the 4 MB limit (a 6.3 MB
// file written; 300 MB to /api/check read whole before a 400).
TEST_F(StudioServerTest, AChunkedBodyIsRefusedBeforeItIsRead) {
  const std::string host = "127.0.0.1:" + std::to_string(port_);
  std::string chunk(1u << 20, 'x');
  std::string head = "PUT /api/file?path=tank/big.coral HTTP/1.1\r\nHost: " + host + "\r\nOrigin: " + origin() +
                     "\r\nContent-Type: text/plain\r\nTransfer-Encoding: chunked\r\n\r\n";
  std::string body;
  for (int i = 0; i < 6; ++i) body += "100000\r\n" + chunk + "\r\n";
  body += "0\r\n\r\n";
  const std::string got = raw_request(port_, head + body);
  EXPECT_EQ(0u, got.find("HTTP/1.1 411")) << got.substr(0, 300);
  EXPECT_NE(std::string::npos, got.find("Content-Length")) << got.substr(0, 300);
  EXPECT_FALSE(fs::exists(base_ / "root/tank/big.coral"));
  // The server goes on.
  auto r = client().Get("/api/files");
  ASSERT_TRUE(r);
  EXPECT_EQ(200, r->status);
}

// Issue 39: a duplicate Host with the good one first, and an empty one,
// were accepted.
TEST_F(StudioServerTest, AHostNamedTwiceOrEmptyIsRefused) {
  const std::string host = "127.0.0.1:" + std::to_string(port_);
  std::string got =
      raw_request(port_, "GET /api/files HTTP/1.1\r\nHost: " + host + "\r\nHost: evil.example:80\r\n\r\n");
  EXPECT_EQ(0u, got.find("HTTP/1.1 400")) << got.substr(0, 300);
  for (const char* none : {"Host: \r\n", ""}) {
    got = raw_request(port_, std::string("GET /api/files HTTP/1.1\r\n") + none + "\r\n");
    EXPECT_EQ(0u, got.find("HTTP/1.1 400")) << got.substr(0, 300);
    EXPECT_NE(std::string::npos, got.find("names this studio's address in Host")) << got.substr(0, 300);
  }
  got = raw_request(port_, "GET /api/files HTTP/1.1\r\nHost: " + host + "\r\n\r\n");
  EXPECT_EQ(0u, got.find("HTTP/1.1 200")) << got.substr(0, 300);
}

// Regression: with a page open (a connection kept alive between its
// requests), stopping the studio waited for the connection's keep-alive to
// run out: Ctrl-C took 5 s. Here the keep-alive is an hour, so a stop that
// waits for it does not return (the wait below is a bound on the test, not
// on the stop).
// A studio on root whose connections are kept alive for an hour: a stop
// that waits for them does not return.
struct LongKeepAliveStudio {
  static StudioOptions options(const fs::path& root) {
    StudioOptions o;
    o.root = root;
    o.keep_alive = std::chrono::hours(1);
    return o;
  }
  explicit LongKeepAliveStudio(const fs::path& root) : server(options(root), hub) {}
  EventHub hub;
  StudioServer server;
};

TEST(StudioServerStop, AConnectionKeptAliveDoesNotHoldTheStop) {
  const fs::path root = make_temp_dir("strata_studio_stop");
  ASSERT_FALSE(root.empty());
  LongKeepAliveStudio studio(root);
  StudioServer& server = studio.server;
  auto port = server.start();
  ASSERT_TRUE(port.ok()) << port.error().message;
  httplib::Client page("127.0.0.1", port.value());
  page.set_keep_alive(true);
  for (int i = 0; i < 2; ++i) {  // the second request on the same connection
    auto r = page.Get("/api/files");
    ASSERT_TRUE(r);
    EXPECT_EQ(200, r->status);
  }
  auto stopped = std::async(std::launch::async, [&server] { server.stop(); });
  const bool in_time = stopped.wait_for(std::chrono::minutes(1)) == std::future_status::ready;
  EXPECT_TRUE(in_time) << "the stop waited on the page's idle connection";
  if (!in_time) page.stop();  // lets the stop end, so the test does
  stopped.get();
  EXPECT_FALSE(page.Get("/api/files"));  // the studio is gone
  fs::remove_all(root);
}

// The same with many pages at once, as many as the workers: connections
// kept alive after a request, connections that sent half a request line and
// connections that sent nothing. The stop ends every one (each client sees
// its end) and leaves no descriptor of them behind.
TEST(StudioServerStop, ManyConnectionsKeptOpenDoNotHoldTheStopAndNoneIsLeft) {
  const fs::path root = make_temp_dir("strata_studio_stop_many");
  ASSERT_FALSE(root.empty());
  const auto open_fds = [] {
    std::size_t n = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator("/proc/self/fd")) ++n;
    return n;
  };
  const std::size_t fds_before = open_fds();
  std::vector<int> clients;
  {
    LongKeepAliveStudio studio(root);
    StudioServer& server = studio.server;
    auto port = server.start();
    ASSERT_TRUE(port.ok()) << port.error().message;
    const std::string host = "127.0.0.1:" + std::to_string(port.value());
    constexpr int kEach = 12;  // 36 in all: under the 48 workers
    for (int kind = 0; kind < 3; ++kind) {
      for (int i = 0; i < kEach; ++i) {
        const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
        ASSERT_GE(fd, 0);
        sockaddr_in addr{};
        addr.sin_family = AF_INET;
        addr.sin_port = htons(port.value());
        addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        ASSERT_EQ(0, ::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr));
        timeval tv{60, 0};  // a bound on the test: a stop that holds fails it
        ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
        clients.push_back(fd);
        if (kind == 0) {  // a page between its requests
          const std::string get = "GET /api/files HTTP/1.1\r\nHost: " + host + "\r\n\r\n";
          ASSERT_EQ(static_cast<ssize_t>(get.size()), ::send(fd, get.data(), get.size(), MSG_NOSIGNAL));
          std::string got;
          char buf[4096];
          while (got.find("\r\n\r\n") == std::string::npos) {
            const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
            ASSERT_GT(n, 0);
            got.append(buf, static_cast<std::size_t>(n));
          }
          EXPECT_EQ(0u, got.find("HTTP/1.1 200")) << got.substr(0, 200);
        } else if (kind == 1) {  // half a request line
          ASSERT_EQ(11, ::send(fd, "GET /api/fi", 11, MSG_NOSIGNAL));
        }
      }
    }
    auto stopped = std::async(std::launch::async, [&server] { server.stop(); });
    const bool in_time = stopped.wait_for(std::chrono::minutes(1)) == std::future_status::ready;
    EXPECT_TRUE(in_time) << "the stop waited on open connections";
    if (!in_time) {
      for (int fd : clients) ::shutdown(fd, SHUT_RDWR);  // lets the stop end, so the test does
    }
    stopped.get();
  }
  // Each client sees its connection end: EOF, or a reset where the server
  // closed with bytes it had not read (the half request line) or had not
  // accepted the connection yet; never the receive timeout of a
  // connection left open.
  for (int fd : clients) {
    char buf[4096];
    ssize_t n = 0;
    while ((n = ::recv(fd, buf, sizeof buf, 0)) > 0) {}
    const int error = n < 0 ? errno : 0;
    EXPECT_TRUE(n == 0 || error == ECONNRESET)
        << "a connection not ended by the stop: recv " << n << ", errno " << error;
    ::close(fd);
  }
  EXPECT_EQ(fds_before, open_fds());
  fs::remove_all(root);
}

// Issue 39: five verifications of a 2^40-state net ran at once, each to
// its own memory limit. A bounded number run; the rest are told when to
// come back.
TEST(StudioSlot, ALimitedNumberAreTakenAndEachIsGivenBack) {
  std::atomic<int> count{0};
  auto a = Slot::take(count, 2);
  auto b = Slot::take(count, 2);
  ASSERT_TRUE(a && b);
  EXPECT_EQ(nullptr, Slot::take(count, 2));
  EXPECT_EQ(2, count.load());
  a.reset();
  EXPECT_EQ(1, count.load());
  EXPECT_NE(nullptr, Slot::take(count, 2));  // taken and given back at once
  EXPECT_EQ(1, count.load());
}

TEST_F(StudioServerTest, VerificationsAndStreamsPastTheirLimitAreToldWhenToComeBack) {
  EventHub hub;
  StudioOptions o;
  o.root = base_ / "root";
  o.max_verifies = 0;
  o.max_streams = 0;
  StudioServer full(o, hub);
  auto port = full.start();
  ASSERT_TRUE(port.ok()) << port.error().message;
  httplib::Client c("127.0.0.1", port.value());
  c.set_read_timeout(10, 0);
  auto v = c.Post("/api/verify", {{"Origin", "http://127.0.0.1:" + std::to_string(port.value())}},
                  R"({"path": "tank/tank.coral"})", "application/json");
  ASSERT_TRUE(v);
  EXPECT_EQ(429, v->status) << v->body;
  EXPECT_EQ("2", v->get_header_value("Retry-After"));
  EXPECT_NE(std::string::npos, v->body.find("--max-verifies")) << v->body;
  auto e = c.Get("/api/events");
  ASSERT_TRUE(e);
  EXPECT_EQ(503, e->status) << e->body;
  EXPECT_EQ(0u, hub.subscribers());
  auto f = c.Get("/api/files");  // the rest of the API is unaffected
  ASSERT_TRUE(f);
  EXPECT_EQ(200, f->status);
}

TEST_F(StudioServerTest, AHundredAndOneHeadersAre431) {
  const std::string host = "127.0.0.1:" + std::to_string(port_);
  std::string request = "GET /api/files HTTP/1.1\r\nHost: " + host + "\r\n";
  for (std::size_t i = 0; i < kMaxHeaders; ++i) request += "X-Filler-" + std::to_string(i) + ": 1\r\n";
  const std::string got = raw_request(port_, request + "\r\n");
  EXPECT_EQ(0u, got.find("HTTP/1.1 431")) << got.substr(0, 300);
  EXPECT_NE(std::string::npos, got.find("101 request headers; at most 100")) << got.substr(0, 300);
}

// Issue 17: any web page could start a run (a cross-origin text/plain POST
// needs no preflight), and DNS rebinding reached the API.
TEST_F(StudioServerTest, ForeignHostsAndOriginsAreRefused) {
  httplib::Client bare("127.0.0.1", port_);
  bare.set_read_timeout(5, 0);
  // GET with a good Host and no Origin: the page and the API.
  for (const char* path : {"/api/files", "/api/primitives"}) {
    auto r = bare.Get(path);
    ASSERT_TRUE(r);
    EXPECT_EQ(200, r->status) << path;
  }
  // A rebound name: refused, GET too.
  auto rebound = bare.Get("/api/files", {{"Host", "evil.example:" + std::to_string(port_)}});
  ASSERT_TRUE(rebound);
  EXPECT_EQ(403, rebound->status);
  EXPECT_TRUE(json::parse(rebound->body).contains("error"));
  auto other_port = bare.Get("/api/files", {{"Host", "127.0.0.1:1"}});
  ASSERT_TRUE(other_port);
  EXPECT_EQ(403, other_port->status);
  auto local = bare.Get("/api/files", {{"Host", "localhost:" + std::to_string(port_)}});
  ASSERT_TRUE(local);
  EXPECT_EQ(200, local->status);
  // A write with no Origin, or another: refused, and nothing happens.
  const std::string run = R"({"path": "tank/tank.coral"})";
  auto none = bare.Post("/api/run", run, "text/plain");
  ASSERT_TRUE(none);
  EXPECT_EQ(403, none->status);
  for (const std::string& origin : std::vector<std::string>{"http://evil.example", "null", "http://127.0.0.1:1",
                                                            "https://127.0.0.1:" + std::to_string(port_),
                                                            "http://evil.example:" + std::to_string(port_)}) {
    auto r = bare.Post("/api/run", {{"Origin", origin}}, run, "text/plain");
    ASSERT_TRUE(r);
    EXPECT_EQ(403, r->status) << origin;
    auto put = bare.Put("/api/file?path=tank/new.coral", {{"Origin", origin}}, "net x {}", "text/plain");
    ASSERT_TRUE(put);
    EXPECT_EQ(403, put->status) << origin;
  }
  EXPECT_TRUE(runs_.empty());
  EXPECT_FALSE(fs::exists(base_ / "root/tank/new.coral"));
  // Its own origin, in both forms.
  for (const std::string& origin : std::vector<std::string>{origin(), "http://localhost:" + std::to_string(port_)}) {
    auto r = bare.Post("/api/run", {{"Origin", origin}}, run, "application/json");
    ASSERT_TRUE(r);
    EXPECT_EQ(202, r->status) << origin << ": " << r->body;
  }
  EXPECT_EQ(2u, runs_.size());
  // A field of the wrong type: 400, as JSON.
  auto typed = bare.Post("/api/check", {{"Origin", origin()}}, R"({"path": 5})", "application/json");
  ASSERT_TRUE(typed);
  EXPECT_EQ(400, typed->status);
  EXPECT_TRUE(json::parse(typed->body, nullptr, false).contains("error")) << typed->body;
  // The library's own errors are JSON too.
  auto nothing = bare.Delete("/api/nothing", {{"Origin", origin()}});
  ASSERT_TRUE(nothing);
  EXPECT_EQ(404, nothing->status);
  EXPECT_TRUE(json::parse(nothing->body, nullptr, false).contains("error")) << nothing->body;
}

}  // namespace
}  // namespace strata::studio
