// The paper's nominal tank mission (missions/tank/tank.coral) run end to end,
// as `strata run` does it: strata::cli::run_mission in this process, the
// embedded simulated vehicle in lockstep on the same io_context, over
// loopback TCP. Console output goes to a stream that discards it.
//
//   run/tank            one whole run, no mission log
//   run/tank/log        the same with the mission log written to a temp file
//     The benchmark's time is wall time per run (ms). Counters:
//       ms_per_run      mean of RunReport::wall_time_s (run_mission's own
//                       clock: from entry to the summary, excluding the
//                       printing of the summary)
//       x_real_time     sum of sim_time_s / sum of wall_time_s over the runs
//       sim_s           simulated seconds one run covers
//     Target: <= 50 ms per run (>= 1000x real time).
//
//   run/tank/reply_to_request
//     Through RunOptions::wire_tap, each line is timestamped (steady_clock)
//     as it arrives from the vehicle (before it is handled) and as a request
//     is written. A reply is `done` (to exec and ood) or `answer` (to ask),
//     protocol.md §4: the replies to the mission's primitive calls. tlm, hb
//     and event are not replies; `ok` (to hello and telemetry, before the
//     mission starts) is left out, and pong and err do not occur in a
//     nominal run. A reply's latency is the time from its arrival to the next line sent,
//     counted only when that line is sent before another reply arrives (so
//     the run's last reply, and a reply after which the mission waits on
//     other requests in flight, give no sample). Counters p50_us, p90_us,
//     p99_us, max_us are over every sample of every run; samples_per_run
//     and replies_per_run show how many replies gave one. The tap only
//     writes into preallocated arrays.
//     Target: p99 <= 20 us.
//
// A run whose exit code is not 0 stops its benchmark with SkipWithError, so a
// broken run is never timed as a success.
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <ostream>
#include <sstream>
#include <streambuf>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "cli/mission_run.h"

namespace strata::cli {
namespace {

using Clock = std::chrono::steady_clock;

constexpr const char* kTankMission = STRATA_SOURCE_DIR "/missions/tank/tank.coral";
constexpr benchmark::IterationCount kLatencyRuns = 200;
// Lines one run may put on the wire (the nominal run has a few hundred);
// more stops the benchmark rather than allocating in the tap.
constexpr std::size_t kMaxLinesPerRun = 16'384;

// Accepts and drops everything, as a console nobody reads.
class NullBuf : public std::streambuf {
 protected:
  int_type overflow(int_type c) override { return traits_type::not_eof(c); }
  std::streamsize xsputn(const char*, std::streamsize n) override { return n; }
};

RunOptions tank_options() {
  RunOptions o;
  o.mission = kTankMission;
  return o;
}

std::string failed_run(const RunReport& report, const std::string& err_text) {
  return fmt::format("run_mission exit code {}{}{}", report.exit_code, err_text.empty() ? "" : ": ",
                     err_text.substr(0, 300));
}

// Runs the mission once more with err captured, to say why a run failed.
std::string why_it_failed(RunOptions options) {
  options.wire_tap = nullptr;
  std::ostringstream err;
  NullBuf null;
  std::ostream out(&null);
  RunReport report = run_mission(options, out, err);
  return failed_run(report, err.str());
}

void bm_run(benchmark::State& st, bool with_log) {
  RunOptions options = tank_options();
  std::filesystem::path log_path;
  if (with_log) {
    log_path = std::filesystem::temp_directory_path() / fmt::format("strata_run_bench_{}.log", ::getpid());
    options.log = log_path.string();
  }
  NullBuf null;
  std::ostream out(&null);
  std::ostream err(&null);
  double sim_s = 0.0;
  double wall_s = 0.0;
  std::int64_t runs = 0;
  for (auto _ : st) {
    RunReport report = run_mission(options, out, err);
    if (report.exit_code != 0) {
      st.SkipWithError(why_it_failed(options).c_str());
      break;
    }
    sim_s += report.sim_time_s;
    wall_s += report.wall_time_s;
    ++runs;
  }
  if (with_log) {
    std::error_code ignored;
    if (runs > 0) st.counters["log_bytes"] = static_cast<double>(std::filesystem::file_size(log_path, ignored));
    std::filesystem::remove(log_path, ignored);
  }
  if (runs == 0) return;
  st.counters["ms_per_run"] = wall_s * 1000.0 / static_cast<double>(runs);
  st.counters["x_real_time"] = wall_s > 0 ? sim_s / wall_s : 0.0;
  st.counters["sim_s"] = sim_s / static_cast<double>(runs);
}

// One line on the wire, as the tap saw it.
enum class Kind : std::uint8_t { kSent, kReply, kOther };

struct Stamp {
  Clock::time_point at;
  Kind kind;
};

bool is_reply(std::string_view line) { return line.substr(0, 5) == "done " || line.substr(0, 7) == "answer "; }

// Sample at quantile q (0..1) of sorted samples, nearest rank (as link_bench).
double quantile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return 0.0;
  auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(sorted.size())));
  return sorted[std::clamp<std::size_t>(rank, 1, sorted.size()) - 1];
}

void bm_reply_to_request(benchmark::State& st) {
  std::vector<Stamp> stamps(kMaxLinesPerRun);
  std::size_t n = 0;
  bool overflow = false;
  RunOptions options = tank_options();
  // Timestamp first, then classify: the arrival time is as early as the tap
  // can see it.
  options.wire_tap = [&](bool sent, std::string_view line) {
    Clock::time_point now = Clock::now();
    if (n == stamps.size()) {
      overflow = true;
      return;
    }
    stamps[n++] = {now, sent ? Kind::kSent : (is_reply(line) ? Kind::kReply : Kind::kOther)};
  };
  NullBuf null;
  std::ostream out(&null);
  std::ostream err(&null);
  std::vector<double> us;
  us.reserve(static_cast<std::size_t>(st.max_iterations) * 512);
  std::int64_t runs = 0;
  std::int64_t replies = 0;
  for (auto _ : st) {
    n = 0;
    overflow = false;
    RunReport report = run_mission(options, out, err);
    if (report.exit_code != 0) {
      st.SkipWithError(why_it_failed(options).c_str());
      break;
    }
    if (overflow) {
      st.SkipWithError(fmt::format("more than {} lines on the wire in one run", kMaxLinesPerRun).c_str());
      break;
    }
    // Outside the timed tap: pair each reply with the first line sent before
    // the next reply arrives.
    bool pending = false;
    Clock::time_point reply_at;
    for (std::size_t i = 0; i < n; ++i) {
      const Stamp& s = stamps[i];
      if (s.kind == Kind::kReply) {
        ++replies;
        pending = true;
        reply_at = s.at;
      } else if (s.kind == Kind::kSent && pending) {
        us.push_back(std::chrono::duration<double, std::micro>(s.at - reply_at).count());
        pending = false;
      }
    }
    ++runs;
  }
  if (runs == 0) return;
  const double samples = static_cast<double>(us.size());
  std::sort(us.begin(), us.end());
  st.counters["p50_us"] = quantile(us, 0.50);
  st.counters["p90_us"] = quantile(us, 0.90);
  st.counters["p99_us"] = quantile(us, 0.99);
  st.counters["max_us"] = us.empty() ? 0.0 : us.back();
  st.counters["samples_per_run"] = samples / static_cast<double>(runs);
  st.counters["replies_per_run"] = static_cast<double>(replies) / static_cast<double>(runs);
}

void register_all() {
  benchmark::RegisterBenchmark("run/tank", [](benchmark::State& st) { bm_run(st, false); })
      ->UseRealTime()
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("run/tank/log", [](benchmark::State& st) { bm_run(st, true); })
      ->UseRealTime()
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("run/tank/reply_to_request", bm_reply_to_request)
      ->Iterations(kLatencyRuns)
      ->UseRealTime()
      ->Unit(benchmark::kMillisecond);
}

}  // namespace
}  // namespace strata::cli

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  strata::cli::register_all();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
