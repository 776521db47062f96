// The studio's cost to a run (issue 7): the nominal tank mission through
// strata::cli::run_mission in lockstep, with and without the studio.
//
// A single run is about 4 ms on the 2-core VM and run-to-run noise is about
// ±15%, more than the effect we are after, so the setups are measured in
// pairs, interleaved: each iteration runs the mission once with no studio
// (the baseline) and once with the studio's RunPublisher telling an
// EventHub that N pages (HTTP clients on loopback) are reading through a
// running `StudioServer`. The two runs of a pair see the same machine
// state, so drift cancels; the order within a pair alternates.
//
//   studio/paired/viewers:0    publisher and hub, nobody reading
//   studio/paired/viewers:20   a server and 20 event streams open and read
//
// For the studio run of a pair the server starts and the pages connect
// (timer paused), and they close after it, so the baseline run has no
// server, no reader threads and no publisher.
//
// Counters (medians over the iterations, wall time of one whole run):
//   base_ms     run without the studio
//   studio_ms   run with the studio
//   overhead_%  median of the per-pair ratio studio/base, minus 1
// Between two runs the timer stops for 100 ms so the streams deliver what
// the run published (pages read it in the next tens of ms): each run is
// measured as a run with pages watching, not as the tail of the last
// one's delivery. Target: 20 viewers slow a lockstep run by less than 10%.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <optional>
#include <sstream>
#include <thread>

#include <httplib.h>

#include "cli/mission_run.h"
#include "studio/run_publisher.h"
#include "studio/server.h"

namespace strata::cli {
namespace {

const std::string kMission = std::string(STRATA_SOURCE_DIR) + "/missions/tank/tank.coral";

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

// One lockstep run; returns its wall time in ms, or a negative value on failure.
double timed_run(studio::RunPublisher* publisher, std::string& error) {
  RunOptions o;
  o.mission = kMission;
  ConsoleOptions console;
  if (publisher) console.observers.push_back(publisher);
  std::ostringstream out, err;
  auto start = std::chrono::steady_clock::now();
  RunReport r = run_mission(o, out, err, console);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  if (r.exit_code != 0) {
    error = err.str();
    return -1;
  }
  return ms;
}

// N pages reading the event stream of a running StudioServer: opened
// before a studio run and closed after it, so the baseline run beside it
// has no server, no reader threads and no publisher at all.
class Viewers {
 public:
  Viewers(studio::EventHub& hub, int n) : hub_(hub) {
    if (n <= 0) return;
    studio::StudioOptions so;
    so.root = std::string(STRATA_SOURCE_DIR) + "/missions";
    server_ = std::make_unique<studio::StudioServer>(so, hub);
    auto port = server_->start();
    if (!port) {
      error = port.error().message;
      return;
    }
    for (int i = 0; i < n; ++i) {
      readers_.emplace_back([this, p = port.value()] {
        httplib::Client c("127.0.0.1", p);
        c.Get("/api/events", [this](const char*, std::size_t k) {
          bytes += k;
          return !stop_.load();
        });
      });
    }
    for (int k = 0; k < 400 && hub.subscribers() < static_cast<std::size_t>(n); ++k) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    if (hub.subscribers() < static_cast<std::size_t>(n)) error = "the viewers did not connect within 2 s";
  }
  ~Viewers() {
    stop_ = true;
    hub_.publish("report", {{"text", "wake the readers"}});
    if (server_) server_->stop();
    for (auto& t : readers_) t.join();
  }
  std::string error;
  static inline std::atomic<std::uint64_t> bytes{0};

 private:
  studio::EventHub& hub_;
  std::unique_ptr<studio::StudioServer> server_;
  std::atomic<bool> stop_{false};
  std::vector<std::thread> readers_;
};

void bm_paired(benchmark::State& st) {
  const int viewers = static_cast<int>(st.range(0));
  Viewers::bytes = 0;
  std::vector<double> base, with, ratio;
  bool studio_first = false;
  std::string error;
  for (auto _ : st) {
    double b = 0, s = 0;
    for (int k = 0; k < 2 && error.empty(); ++k) {
      const bool use_studio = (k == 0) == studio_first;
      if (!use_studio) {
        b = timed_run(nullptr, error);
      } else {
        st.PauseTiming();
        studio::EventHub hub;
        studio::RunPublisher publisher(hub);
        std::optional<Viewers> pages(std::in_place, hub, viewers);
        error = pages->error;
        st.ResumeTiming();
        if (error.empty()) s = timed_run(&publisher, error);
        st.PauseTiming();
        // Let the pages read what the run published before they close.
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        pages.reset();
        st.ResumeTiming();
      }
      st.PauseTiming();
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      st.ResumeTiming();
    }
    if (!error.empty()) {
      st.SkipWithError(error.c_str());
      break;
    }
    studio_first = !studio_first;
    base.push_back(b);
    with.push_back(s);
    ratio.push_back(s / b);
  }
  st.counters["base_ms"] = median(base);
  st.counters["studio_ms"] = median(with);
  st.counters["overhead_%"] = (median(ratio) - 1) * 100;
  st.counters["stream_MB"] = static_cast<double>(Viewers::bytes.load()) / 1e6;
}

BENCHMARK(bm_paired)
    ->Name("studio/paired")
    ->ArgName("viewers")
    ->Arg(0)
    ->Arg(20)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(60);

}  // namespace
}  // namespace strata::cli

BENCHMARK_MAIN();
