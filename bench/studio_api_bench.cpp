// The studio's answers a page waits for (issue 17's targets: page load to
// file list <= 150 ms on loopback; the tank mission open <= 100 ms), over
// loopback against a running StudioServer on a copy of missions/:
//
//   studio/api/page_load     GET / (as a browser asks: Accept-Encoding
//                            gzip, deflate, br), then GET /api/files, on a
//                            fresh connection each: what a page load costs
//                            the server up to its file list
//   studio/api/mission_open  GET /api/mission?path=tank/tank.coral (read,
//                            compile with its 4 imports, the model as JSON)
//
// Counters: bytes of the answers. The page served is the one embedded in
// this build (the Vite page when web/node_modules was there at build time,
// else the short page that says it was not built: see the output's
// "page_built" counter).
#include <benchmark/benchmark.h>

#include <stdlib.h>

#include <filesystem>
#include <memory>
#include <string>

#include <httplib.h>

#include "studio/assets.h"
#include "studio/server.h"

namespace strata::studio {
namespace {

namespace fs = std::filesystem;

// A studio on a fresh copy of missions/, for the whole benchmark.
class Studio {
 public:
  Studio() {
    std::string pattern = (fs::temp_directory_path() / "strata_api_bench_XXXXXX").string();
    if (!mkdtemp(pattern.data())) return;
    dir_ = pattern;
    fs::copy(fs::path(STRATA_SOURCE_DIR) / "missions", dir_ / "missions", fs::copy_options::recursive);
    StudioOptions o;
    o.root = dir_ / "missions";
    server_ = std::make_unique<StudioServer>(o, hub_);
    auto port = server_->start();
    if (port) port_ = port.value();
  }
  ~Studio() {
    server_.reset();
    std::error_code ec;
    if (!dir_.empty()) fs::remove_all(dir_, ec);
  }
  std::uint16_t port() const { return port_; }

 private:
  fs::path dir_;
  EventHub hub_;
  std::unique_ptr<StudioServer> server_;
  std::uint16_t port_ = 0;
};

Studio& studio() {
  static Studio s;
  return s;
}

void bm_page_load(benchmark::State& state) {
  const std::uint16_t port = studio().port();
  if (port == 0) return state.SkipWithError("the studio did not start");
  std::size_t bytes = 0;
  for (auto _ : state) {
    httplib::Client c("127.0.0.1", port);
    c.set_decompress(false);  // as sent; the browser's decoding is not the server's cost
    auto page = c.Get("/", {{"Accept-Encoding", "gzip, deflate, br"}});
    auto files = c.Get("/api/files");
    if (!page || page->status != 200 || !files || files->status != 200) {
      return state.SkipWithError("a request failed");
    }
    bytes = page->body.size() + files->body.size();
  }
  state.counters["bytes"] = static_cast<double>(bytes);
  state.counters["page_built"] = page_built() ? 1 : 0;
}

void bm_mission_open(benchmark::State& state) {
  const std::uint16_t port = studio().port();
  if (port == 0) return state.SkipWithError("the studio did not start");
  httplib::Client c("127.0.0.1", port);
  c.set_keep_alive(true);
  std::size_t bytes = 0;
  for (auto _ : state) {
    auto r = c.Get("/api/mission?path=tank/tank.coral", {{"Accept-Encoding", "gzip, deflate, br"}});
    if (!r || r->status != 200) return state.SkipWithError("GET /api/mission failed");
    bytes = r->body.size();
  }
  state.counters["bytes"] = static_cast<double>(bytes);
}

BENCHMARK(bm_page_load)->Name("studio/api/page_load")->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(bm_mission_open)->Name("studio/api/mission_open")->Unit(benchmark::kMillisecond)->MinTime(2.0);

}  // namespace
}  // namespace strata::studio
