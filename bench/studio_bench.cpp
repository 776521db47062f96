// The studio's cost to a run (issue 7): the nominal tank mission through
// strata::cli::run_mission in lockstep, with the studio's RunPublisher
// telling an EventHub, and 0 or 20 pages (HTTP clients on loopback) reading
// the event stream of a running `StudioServer`.
//
//   studio/lockstep/viewers:0    no studio at all (the baseline)
//   studio/lockstep/viewers:-1   the publisher and the hub, nobody reading
//   studio/lockstep/viewers:20   20 event streams open and read
//
// Counter ms_per_run: wall time of one whole run. Between two runs the
// timer stops for 150 ms so the streams deliver what the run published (a
// run is a few ms; its pages read it in the next tens of ms): each run is
// measured as a run with 20 pages watching, not as the tail of the last
// one's delivery. Target: 20 viewers slow a lockstep run by less than 10%
// against the baseline.
#include <benchmark/benchmark.h>

#include <atomic>
#include <chrono>
#include <sstream>
#include <thread>

#include <httplib.h>

#include "cli/mission_run.h"
#include "studio/run_publisher.h"
#include "studio/server.h"

namespace strata::cli {
namespace {

const std::string kMission = std::string(STRATA_SOURCE_DIR) + "/missions/tank/tank.coral";

void bm_run(benchmark::State& st) {
  const int viewers = static_cast<int>(st.range(0));
  studio::EventHub hub;
  studio::RunPublisher publisher(hub);
  std::unique_ptr<studio::StudioServer> server;
  std::atomic<bool> stop{false};
  std::atomic<std::uint64_t> bytes{0};
  std::vector<std::thread> readers;
  if (viewers > 0) {
    studio::StudioOptions so;
    so.root = std::string(STRATA_SOURCE_DIR) + "/missions";
    server = std::make_unique<studio::StudioServer>(so, hub);
    auto port = server->start();
    if (!port) {
      st.SkipWithError(port.error().message.c_str());
      return;
    }
    for (int i = 0; i < viewers; ++i) {
      readers.emplace_back([&, p = port.value()] {
        httplib::Client c("127.0.0.1", p);
        c.Get("/api/events", [&](const char*, std::size_t n) {
          bytes += n;
          return !stop.load();
        });
      });
    }
    while (hub.subscribers() < static_cast<std::size_t>(viewers)) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  double total_ms = 0;
  std::uint64_t runs = 0;
  for (auto _ : st) {
    RunOptions o;
    o.mission = kMission;
    if (viewers != 0) {
      o.observers.push_back(&publisher);
      o.on_telemetry = [&](const protocol::Telemetry& t) { publisher.telemetry(t.sim_time_s, t.depth_m.value_or(0), t.setpoint_m); };
      o.on_report = [&](const std::string& text, double t) { publisher.report(t, text); };
    }
    std::ostringstream out, err;
    auto start = std::chrono::steady_clock::now();
    RunReport r = run_mission(o, out, err);
    total_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    ++runs;
    if (r.exit_code != 0) {
      st.SkipWithError(err.str().c_str());
      break;
    }
    st.PauseTiming();
    std::this_thread::sleep_for(std::chrono::milliseconds(150));
    st.ResumeTiming();
  }
  st.counters["ms_per_run"] = runs ? total_ms / static_cast<double>(runs) : 0;
  st.counters["stream_MB"] = static_cast<double>(bytes.load()) / 1e6;
  stop = true;
  hub.publish("report", {{"text", "wake the readers"}});
  if (server) server->stop();
  for (auto& t : readers) t.join();
}

BENCHMARK(bm_run)->Name("studio/lockstep")->ArgName("viewers")->Arg(0)->Arg(-1)->Arg(20)->Unit(benchmark::kMillisecond)->Iterations(40);

}  // namespace
}  // namespace strata::cli

BENCHMARK_MAIN();
