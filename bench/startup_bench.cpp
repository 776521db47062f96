// Whole-process start-up of PROLOG commands (issue 41): each benchmark runs
// two commands in turn, one process each per iteration (posix_spawn, wait),
// output to /dev/null, and reports the median wall time of each (a_ms,
// b_ms) and their ratio (b_over_a), measured side by side in one run.
//
//   startup/check_pl_vs_swipl     swipl -g halt | strata check tank.pl
//                                 target: b_over_a <= 2
//   startup/check_pl_text_vs_swipl  the same with STRATA_PROLOG_DRIVER=""
//                                 (the driver compiled from its text)
//   startup/run_pl_vs_coral       strata run tank.coral | strata run tank.pl
//   startup/check_coral_vs_swipl  swipl -g halt | strata check tank.coral
//   pnml/MODEL                    strata verify --pnml | strata-pnml, the
//                                 whole state space of each net of
//                                 ../shared/pnml when present, with LoLA 2's
//                                 time for the same (lola_ms, b_over_lola;
//                                 target <= 0.25) and the peak RSS of both
//                                 (a_rss_mib, b_rss_mib; target on the
//                                 smallest net <= LoLA's 5.7 MiB)
//
// strata is the one built beside this program (STRATA_EXE), which finds the
// precompiled driver beside it; swipl the one the build found. A command
// that does not exit 0 stops its benchmark with SkipWithError.
#include <benchmark/benchmark.h>

#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

extern char** environ;

namespace {

using Clock = std::chrono::steady_clock;

constexpr const char* kTankProlog = STRATA_SOURCE_DIR "/missions/tank/tank.pl";
constexpr const char* kTankCoral = STRATA_SOURCE_DIR "/missions/tank/tank.coral";

struct Command {
  std::vector<std::string> argv;
  bool driver_text = false;  // STRATA_PROLOG_DRIVER="" (the driver from its text)
};

struct Ran {
  double seconds = -1.0;  // wall; negative when it did not start or did not exit 0
  // Peak resident set (wait4's ru_maxrss). The child starts as a copy of
  // this process's memory, so the figure is never under this benchmark's
  // own resident size at the spawn (a few MiB: check it with
  // /usr/bin/time when a figure comes near it).
  double rss_mib = 0.0;
};

// Runs command to its end.
Ran run(const Command& command) {
  std::vector<char*> argv;
  argv.reserve(command.argv.size() + 1);
  for (const auto& a : command.argv) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  std::vector<std::string> env_text;
  for (char** e = environ; *e != nullptr; ++e) {
    std::string entry(*e);
    if (entry.rfind("STRATA_PROLOG_DRIVER=", 0) != 0) env_text.push_back(entry);
  }
  if (command.driver_text) env_text.emplace_back("STRATA_PROLOG_DRIVER=");
  std::vector<char*> env;
  env.reserve(env_text.size() + 1);
  for (auto& e : env_text) env.push_back(e.data());
  env.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  const auto start = Clock::now();
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), env.data());
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) return {};
  int status = 0;
  rusage usage{};
  if (wait4(pid, &status, 0, &usage) != pid) return {};
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) return {};
  return {seconds, static_cast<double>(usage.ru_maxrss) / 1024.0};
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2.0;
}

// lola_s > 0: LoLA's time for what b does, for b_over_lola.
void bm_pair(benchmark::State& st, const Command& a, const Command& b, double lola_s = 0.0) {
  std::vector<double> as;
  std::vector<double> bs;
  std::vector<double> a_rss;
  std::vector<double> b_rss;
  for (auto _ : st) {
    const Ran ra = run(a);
    const Ran rb = run(b);
    if (ra.seconds < 0 || rb.seconds < 0) {
      const std::string why = (ra.seconds < 0 ? a : b).argv[0] + " did not exit 0";
      st.SkipWithError(why.c_str());
      return;
    }
    as.push_back(ra.seconds);
    bs.push_back(rb.seconds);
    a_rss.push_back(ra.rss_mib);
    b_rss.push_back(rb.rss_mib);
  }
  if (as.empty()) return;
  st.counters["a_ms"] = median(as) * 1000.0;
  st.counters["b_ms"] = median(bs) * 1000.0;
  st.counters["b_over_a"] = median(bs) / median(as);
  st.counters["a_rss_mib"] = median(a_rss);
  st.counters["b_rss_mib"] = median(b_rss);
  if (lola_s > 0) {
    st.counters["lola_ms"] = lola_s * 1000.0;
    st.counters["b_over_lola"] = median(bs) / lola_s;
  }
}

// model -> LoLA 2's full state-space seconds (lola-deadlock.csv), in the
// file's order.
std::vector<std::pair<std::string, double>> lola_full_times() {
  namespace fs = std::filesystem;
  std::vector<std::pair<std::string, double>> out;
  std::ifstream in(fs::path(STRATA_SOURCE_DIR) / ".." / "shared" / "pnml" / "lola-deadlock.csv");
  std::string line;
  if (!std::getline(in, line)) return out;
  std::vector<std::string> header;
  std::stringstream hs(line);
  for (std::string cell; std::getline(hs, cell, ',');) header.push_back(cell);
  const auto column = std::find(header.begin(), header.end(), "lola_full_s") - header.begin();
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ls(line);
    for (std::string cell; std::getline(ls, cell, ',');) cells.push_back(cell);
    if (cells.size() <= static_cast<std::size_t>(column)) continue;
    out.emplace_back(cells[0], std::stod(cells[static_cast<std::size_t>(column)]));
  }
  return out;
}

void register_all() {
  const Command swipl{{SWIPL_EXE, "-g", "halt"}};
  const Command check_pl{{STRATA_EXE, "check", kTankProlog}};
  const Command check_pl_text{{STRATA_EXE, "check", kTankProlog}, true};
  const Command check_coral{{STRATA_EXE, "check", kTankCoral}};
  const Command run_pl{{STRATA_EXE, "run", kTankProlog}};
  const Command run_coral{{STRATA_EXE, "run", kTankCoral}};
  auto add = [](const char* name, const Command& a, const Command& b) {
    benchmark::RegisterBenchmark(name, [a, b](benchmark::State& st) { bm_pair(st, a, b); })
        ->UseRealTime()
        ->Unit(benchmark::kMillisecond)
        ->Iterations(20);
  };
  add("startup/check_pl_vs_swipl", swipl, check_pl);
  add("startup/check_pl_text_vs_swipl", swipl, check_pl_text);
  add("startup/run_pl_vs_coral", run_coral, run_pl);
  add("startup/check_coral_vs_swipl", swipl, check_coral);
  const auto pnml_dir = std::filesystem::path(STRATA_SOURCE_DIR) / ".." / "shared" / "pnml";
  for (const auto& [model, lola_s] : lola_full_times()) {
    const std::string net = (pnml_dir / model / "model.pnml").string();
    const Command verify{{STRATA_EXE, "verify", "--pnml", net}};
    const Command lean{{STRATA_PNML_EXE, net}};
    const double lola = lola_s;
    benchmark::RegisterBenchmark(("pnml/" + model).c_str(),
                                 [verify, lean, lola](benchmark::State& st) { bm_pair(st, verify, lean, lola); })
        ->UseRealTime()
        ->Unit(benchmark::kMillisecond)
        ->Iterations(lola < 1.0 ? 9 : 3);
  }
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  register_all();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
