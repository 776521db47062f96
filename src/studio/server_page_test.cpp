// The studio server's page from disk (`--web-root`) and its life: a stop
// right after the start; over loopback.
#include <sys/stat.h>

#include <cstdlib>
#include <future>

#include <fmt/format.h>

#include "studio/server_test_support.h"

namespace strata::studio {
namespace {

// `strata studio --web-root DIR` (docs/studio.md, "Use"): the page from disk,
// through the same sandbox as the missions. Regression: it was read with an
// ifstream, so a FIFO planted in the folder held an HTTP worker for ever (and
// the sonar scan's latest.png the same).
TEST(StudioWebRoot, ServesThePageFromDiskAndNothingElse) {
  const fs::path base = make_temp_dir("strata_webroot");
  ASSERT_FALSE(base.empty());
  fs::create_directories(base / "root");
  fs::create_directories(base / "web/assets");
  fs::create_directories(base / "sonar");
  std::ofstream(base / "web/index.html") << "<p>the page on disk</p>";
  std::ofstream(base / "web/assets/app.js") << "console.log('disk');";
  std::ofstream(base / "secret.txt") << "outside";
  fs::create_symlink(base / "secret.txt", base / "web/leak.js");
  ASSERT_EQ(0, ::mkfifo((base / "web/pipe.js").c_str(), 0600));
  ASSERT_EQ(0, ::mkfifo((base / "sonar/latest.png").c_str(), 0600));
  EventHub hub;
  StudioOptions o;
  o.root = base / "root";
  o.web_root = base / "web";
  o.sonar_dir = base / "sonar";
  o.threads = 4;
  {
    StudioServer server(o, hub);
    auto port = server.start();
    ASSERT_TRUE(port.ok()) << port.error().message;
    httplib::Client c("127.0.0.1", port.value());
    c.set_read_timeout(5, 0);
    auto page = c.Get("/");
    ASSERT_TRUE(page);
    EXPECT_EQ(200, page->status);
    EXPECT_EQ("<p>the page on disk</p>", page->body);
    auto js = c.Get("/assets/app.js");
    ASSERT_TRUE(js);
    EXPECT_EQ("console.log('disk');", js->body);
    // More FIFO reads than the server has workers: each must be answered.
    for (int i = 0; i < 6; ++i) {
      for (const char* path : {"/pipe.js", "/api/sonar/latest.png"}) {
        auto r = c.Get(path);
        ASSERT_TRUE(r) << path << " was not answered";
        EXPECT_EQ(404, r->status) << path;
      }
    }
    for (const char* path : {"/leak.js", "/../secret.txt", "/%2e%2e/secret.txt", "/nothing.js"}) {
      auto r = c.Get(path);
      ASSERT_TRUE(r) << path;
      EXPECT_EQ(404, r->status) << path;
      EXPECT_EQ(std::string::npos, r->body.find("outside")) << path;
    }
  }
  fs::remove_all(base);
}

// Regression: a stop() right after start() (Ctrl-C as `strata studio`
// printed its URL) came before cpp-httplib's accept loop, where its stop()
// does nothing, so the listener ran on and stop() joined it for ever: about
// one start in ten never ended. Each stop here must end within 10 s.
TEST(StudioServerLife, AStopRightAfterTheStartEnds) {
  const fs::path root = make_temp_dir("strata_stopnow");
  ASSERT_FALSE(root.empty());
  for (int i = 0; i < 60; ++i) {
    EventHub hub;
    StudioOptions o;
    o.root = root;
    o.threads = 2;
    auto server = std::make_unique<StudioServer>(o, hub);
    ASSERT_TRUE(server->start().ok());
    auto stopped = std::async(std::launch::async, [&server] { server->stop(); });
    if (stopped.wait_for(10s) != std::future_status::ready) {
      ADD_FAILURE() << "stop() right after start() did not end within 10 s (start " << i << ")";
      std::_Exit(1);  // the listener would hold the test for ever
    }
  }
  fs::remove_all(root);
}

// The server takes its runner from its caller only: without one it starts
// no run of its own (it used to make a spare StudioRunner), and says so.
TEST(StudioServerLife, AServerGivenNoRunnerRunsNoMissions) {
  const fs::path root = make_temp_dir("strata_norunner");
  ASSERT_FALSE(root.empty());
  fs::copy(fs::path(STRATA_SOURCE_DIR) / "missions/tank", root / "tank", fs::copy_options::recursive);
  EventHub hub;
  StudioOptions o;
  o.root = root;
  o.threads = 2;
  {
    StudioServer server(o, hub);
    auto port = server.start();
    ASSERT_TRUE(port.ok()) << port.error().message;
    httplib::Client c("127.0.0.1", port.value());
    c.set_read_timeout(5, 0);
    const httplib::Headers origin{{"Origin", fmt::format("http://127.0.0.1:{}", port.value())}};
    auto run = c.Post("/api/run", origin, R"({"path": "tank/tank.coral"})", "application/json");
    ASSERT_TRUE(run);
    EXPECT_EQ(503, run->status) << run->body;
    EXPECT_NE(std::string::npos, run->body.find("runs no missions")) << run->body;
    for (const char* path : {"/api/run/stop", "/api/run/abort"}) {
      auto r = c.Post(path, origin, "{}", "application/json");
      ASSERT_TRUE(r) << path;
      EXPECT_EQ(200, r->status) << path;  // nothing to stop
    }
  }
  fs::remove_all(root);
}

}  // namespace
}  // namespace strata::studio
