#pragma once
// The fixture of the studio server's API tests: a server over loopback on a
// copy of missions/tank in a fresh folder (with a file outside it), its runs
// recorded by a fake launcher instead of run.
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <httplib.h>

#include "studio/server.h"

namespace strata::studio {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using nlohmann::json;

// A fresh folder under the test's temp folder (mkdtemp: its own, 0700), or
// an empty path with the test failed.
inline fs::path make_temp_dir(const std::string& prefix) {
  std::string pattern = (fs::path(::testing::TempDir()) / (prefix + "_XXXXXX")).string();
  if (mkdtemp(pattern.data()) == nullptr) {
    ADD_FAILURE() << "mkdtemp failed for " << pattern;
    return {};
  }
  return pattern;
}

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

class StudioServerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    base_ = make_temp_dir("strata_studio");
    ASSERT_FALSE(base_.empty());
    fs::create_directories(base_ / "root");
    fs::copy(fs::path(STRATA_SOURCE_DIR) / "missions/tank", base_ / "root/tank", fs::copy_options::recursive);
    std::ofstream(base_ / "secret.coral") << "net secret {}";
    StudioOptions o;
    o.root = base_ / "root";
    o.sonar_dir = base_ / "sonar";
    o.heartbeat = 100ms;
    o.watch_period = 50ms;
    o.runs = &launcher_;
    server_ = std::make_unique<StudioServer>(o, hub_);
    auto port = server_->start();
    ASSERT_TRUE(port.ok()) << port.error().message;
    port_ = port.value();
  }
  void TearDown() override {
    server_.reset();
    fs::remove_all(base_);
  }
  httplib::Client client() {
    httplib::Client c("127.0.0.1", port_);
    c.set_read_timeout(5, 0);
    c.set_connection_timeout(5, 0);
    // As the page: its writes carry the studio's own origin.
    c.set_default_headers({{"Origin", origin()}});
    return c;
  }
  std::string origin() const { return "http://127.0.0.1:" + std::to_string(port_); }
  // The ETag of a file as GET /api/mission gives it.
  std::string etag_of(const std::string& path) {
    auto r = client().Get(("/api/mission?path=" + path).c_str());
    return r ? r->get_header_value("ETag") : std::string();
  }

  fs::path base_;
  EventHub hub_;
  std::unique_ptr<StudioServer> server_;
  std::uint16_t port_ = 0;
  // Records the runs asked for instead of running them.
  struct Launcher final : RunLauncher {
    core::Result<void> start(const RunRequest& r) override {
      runs.push_back(r);
      return core::Result<void>();
    }
    void abort() override { ++aborts; }
    void stop() override { ++stops; }
    std::vector<RunRequest> runs;
    int stops = 0;
    int aborts = 0;
  };
  Launcher launcher_;
  std::vector<RunRequest>& runs_ = launcher_.runs;
};

}  // namespace strata::studio
