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
//   studio/api/chain_open    GET /api/mission of a 5,000-transition chain
//   studio/api/chain_edit    POST /api/edit add_place on that chain, with the
//                            model held as base: the server's part of the
//                            page's edit round trip (target <= 300 ms in all)
//
// Counters: bytes of the answers. The page served is the one embedded in
// this build (the Vite page when web/node_modules was there at build time,
// else the short page that says it was not built: see the output's
// "page_built" counter).
#include <benchmark/benchmark.h>

#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "studio/assets.h"
#include "studio/server.h"

namespace strata::studio {
namespace {

namespace fs = std::filesystem;

// net chain: p0 -> t1 -> p1 -> ... -> t_n -> done, the browser test's chain.
std::string chain_text(int n) {
  std::string s = "net chain {\n  place p0 = 1;\n";
  for (int i = 1; i < n; ++i) s += "  place p" + std::to_string(i) + ";\n";
  s += "  exit done;\n";
  for (int i = 1; i <= n; ++i) {
    s += "  transition t" + std::to_string(i) + " { wait { p" + std::to_string(i - 1) + " } signal { " +
         (i < n ? "p" + std::to_string(i) : std::string("done")) + " } }\n";
  }
  return s + "}\n";
}

// A studio on a fresh copy of missions/, for the whole benchmark.
class Studio {
 public:
  Studio() {
    std::string pattern = (fs::temp_directory_path() / "strata_api_bench_XXXXXX").string();
    if (!mkdtemp(pattern.data())) return;
    dir_ = pattern;
    fs::copy(fs::path(STRATA_SOURCE_DIR) / "missions", dir_ / "missions", fs::copy_options::recursive);
    chain_ = chain_text(5000);
    std::ofstream(dir_ / "missions" / "chain.coral") << chain_;
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
  const std::string& chain() const { return chain_; }

 private:
  fs::path dir_;
  EventHub hub_;
  std::unique_ptr<StudioServer> server_;
  std::uint16_t port_ = 0;
  std::string chain_;
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

void bm_chain_open(benchmark::State& state) {
  const std::uint16_t port = studio().port();
  if (port == 0) return state.SkipWithError("the studio did not start");
  httplib::Client c("127.0.0.1", port);
  c.set_keep_alive(true);
  c.set_decompress(false);
  std::size_t bytes = 0;
  for (auto _ : state) {
    auto r = c.Get("/api/mission?path=chain.coral", {{"Accept-Encoding", "gzip, deflate, br"}});
    if (!r || r->status != 200) return state.SkipWithError("GET /api/mission failed");
    bytes = r->body.size();
  }
  state.counters["bytes"] = static_cast<double>(bytes);
}

void bm_chain_edit(benchmark::State& state) {
  const std::uint16_t port = studio().port();
  if (port == 0) return state.SkipWithError("the studio did not start");
  httplib::Client c("127.0.0.1", port);
  c.set_keep_alive(true);
  const std::string origin = "http://127.0.0.1:" + std::to_string(port);
  const httplib::Headers headers = {{"Origin", origin}, {"Accept-Encoding", "gzip, deflate, br"}};
  std::size_t bytes = 0;
  for (auto _ : state) {
    state.PauseTiming();  // the base: a model the server keeps (it keeps a few)
    auto open = c.Get("/api/mission?path=chain.coral");
    if (!open || open->status != 200) return state.SkipWithError("GET /api/mission failed");
    const std::string rev = nlohmann::json::parse(open->body).value("rev", "");
    const std::string body = nlohmann::json{
        {"path", "chain.coral"},
        {"text", studio().chain()},
        {"op", {{"op", "add_place"}, {"net", "chain"}, {"name", "extra"}}},
        {"base", rev}}.dump();
    state.ResumeTiming();
    auto r = c.Post("/api/edit", headers, body, "application/json");
    if (!r || r->status != 200) return state.SkipWithError("POST /api/edit failed");
    bytes = r->body.size();
  }
  state.counters["bytes"] = static_cast<double>(bytes);
}

BENCHMARK(bm_page_load)->Name("studio/api/page_load")->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(bm_mission_open)->Name("studio/api/mission_open")->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(bm_chain_open)->Name("studio/api/chain_open")->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(bm_chain_edit)->Name("studio/api/chain_edit")->Unit(benchmark::kMillisecond)->MinTime(2.0);

}  // namespace
}  // namespace strata::studio
