// A guard's reaction (issue 37's target): from the moment its condition
// becomes true on the vehicle to the handler's first primitive call, at most
// one poll period plus one control cycle. A guarded mission holds at 2 m
// (docs/language.md, "guard": `leak`, every 1 s, on system_problem); a
// leak starts at a time spread over one poll period and more; the mission
// log gives when the handler's first call went out. One trip per run.
//
//   guard/reaction/lockstep        1,000 trips, lockstep (the embedded vehicle)
//   guard/reaction/realtime/10       100 trips on the wall clock at 10x
//
// Counters, in simulated seconds from the leak to the handler's first call:
// p50_s, p99_s, max_s, and bound_s = the period plus one control cycle
// (1.1 s); over_bound counts the trips later than the bound. The time per
// iteration is one whole run.
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <sstream>
#include <streambuf>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/mission_run.h"

namespace strata::cli {
namespace {

constexpr double kPeriod = 1.0;
constexpr double kCycle = 0.1;  // the vehicle's control cycle (config/phoenix.toml)

constexpr const char* kMission = R"(// A guarded hold at 2 m: the guard surfaces the vehicle on a leak.
mission hold {
  place begin = 1, up, down, held, rising, surfaced;
  exit completed, aborted;
  guard leak every 1 {
    when   { system_problem }
    action { TACTIC(EXEC, surface, rising) }
  }
  transition start { wait { begin }   action { TACTIC(OOD, start_network, up) } }
  transition dive  { wait { up }      action { TACTIC(EXEC, goto_depth(2), down) } }
  transition hold  { wait { down }    action { TACTIC(EXEC, sleep(600), held) } }
  transition done  { wait { held }    action { TACTIC(OOD, shutdown_network, completed) } }
  transition close { wait { rising }  action { TACTIC(OOD, shutdown_network, aborted) } }
}
)";

class NullBuf : public std::streambuf {
 protected:
  int_type overflow(int_type c) override { return traits_type::not_eof(c); }
  std::streamsize xsputn(const char*, std::streamsize n) override { return n; }
};

double quantile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return 0.0;
  auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(sorted.size())));
  return sorted[std::clamp<std::size_t>(rank, 1, sorted.size()) - 1];
}

// The sim time of the first request after the guard_tripped line, or -1.
double handler_first_call(const std::filesystem::path& log) {
  std::ifstream in(log);
  std::string line;
  bool tripped = false;
  while (std::getline(in, line)) {
    const auto j = nlohmann::json::parse(line, nullptr, false);
    if (j.is_discarded()) continue;
    const std::string event = j.value("event", "");
    if (event == "guard_tripped") tripped = true;
    if (tripped && event == "request") return j.value("sim_time", -1.0);
  }
  return -1.0;
}

void bm_reaction(benchmark::State& st, bool realtime, double speed) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / fmt::format("strata_guard_bench_{}", ::getpid());
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "hold.coral") << kMission;
  NullBuf null;
  std::ostream out(&null);
  std::ostream err(&null);
  std::vector<double> reaction;
  std::int64_t runs = 0;
  for (auto _ : st) {
    // Leaks spread evenly over [5, 7) s: two poll periods, every phase of the cycle.
    const double leak_s = 5.0 + 2.0 * static_cast<double>(runs % 1000) / 1000.0;
    std::ofstream(dir / "leak.toml") << fmt::format("seed = {}\n[[fault]]\nkind = \"leak\"\nat_s = {}\n", runs + 1,
                                                    leak_s);
    RunOptions o;
    o.mission = (dir / "hold.coral").string();
    o.scenario = (dir / "leak.toml").string();
    o.log = (dir / "run.jsonl").string();
    o.realtime = realtime;
    o.speed = speed;
    RunReport report = run_mission(o, out, err);
    const double first = handler_first_call(dir / "run.jsonl");
    if (report.exit_code != 1 || first < 0) {
      st.SkipWithError(fmt::format("run {}: exit {}, no handler call found", runs, report.exit_code).c_str());
      break;
    }
    reaction.push_back(first - leak_s);
    ++runs;
  }
  std::error_code ignored;
  std::filesystem::remove_all(dir, ignored);
  if (reaction.empty()) return;
  std::sort(reaction.begin(), reaction.end());
  st.counters["p50_s"] = quantile(reaction, 0.5);
  st.counters["p99_s"] = quantile(reaction, 0.99);
  st.counters["max_s"] = reaction.back();
  st.counters["bound_s"] = kPeriod + kCycle;
  st.counters["over_bound"] = static_cast<double>(
      std::count_if(reaction.begin(), reaction.end(), [](double r) { return r > kPeriod + kCycle + 1e-6; }));
}

BENCHMARK_CAPTURE(bm_reaction, lockstep, false, 1.0)
    ->Name("guard/reaction/lockstep")
    ->Iterations(1000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(bm_reaction, realtime_10, true, 10.0)
    ->Name("guard/reaction/realtime/10")
    ->Iterations(100)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace strata::cli

BENCHMARK_MAIN();
