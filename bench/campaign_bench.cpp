// A campaign against its two yardsticks (issue 41), measured side by side
// in one run of one benchmark:
//
//   campaign/tank   the example campaign (missions/tank/campaign.toml, its
//                   456 cases in both forms), three ways in turn:
//     campaign      `strata campaign SPEC --out TMP -j 2 -q`, one process
//                   (its workers forked), wall time to its exit;
//     per_process   the same cases as one `strata run` process each, two
//                   at a time, wall time to the last: each case's scenario
//                   (and perturbed vehicle) written to a file first, the
//                   command the campaign's repro_run line gives
//                   (`strata run MISSION --scenario FILE [--params FILE]
//                   --max-sim-time S --telemetry-hz HZ`, with --no-log);
//     in_process    the nominal tank mission run in this process (as
//                   run_bench's run/tank: strata::cli::run_mission, lockstep,
//                   the embedded vehicle, telemetry at the run's default
//                   2 Hz, no log), median wall time of one run; and the same
//                   at the spec's telemetry rate (10 Hz: the campaign samples
//                   the depth five times as often) as in_process_spec_hz;
//     cases_in_process  every case of the spec, one after another in this
//                   process, as one worker runs them
//                   (strata::campaign::run_case, no output folder): its own
//                   mission, fault, perturbed vehicle and length, and the
//                   PROLOG start in this process at its first tank.pl case;
//                   wall time to the last.
//   Counters:
//     cases                  the spec's cases
//     campaign_cases_per_s   cases / campaign wall
//     per_process_cases_per_s
//     campaign_over_per_process   target: >= 2
//     limit_cases_per_s      cores / in_process (the machine's cores)
//     campaign_over_limit         target: >= 0.8
//     in_process_ms          the median run
//     in_process_spec_hz_ms  the same at the spec's telemetry rate
//     campaign_over_spec_hz_limit  cases/s over cores / in_process_spec_hz
//     cases_in_process_ms    cases_in_process / cases: a case's mean run
//     campaign_over_cases_limit   cases/s over cores / cases_in_process_ms:
//                            what the pool (workers, hand-offs, results)
//                            keeps of the machine, for these very cases
//   Each iteration takes a few seconds (most of it the per-process way);
//   --benchmark_repetitions gives several.
//
// strata is the one built beside this program (STRATA_EXE). A campaign
// that does not exit 0 (every case of the example passes), a `strata run`
// that exits 64 or more (a leak case's run aborts: exit 1), or an
// in-process run that does not complete stops the benchmark with
// SkipWithError.
#include <benchmark/benchmark.h>

#include <fcntl.h>
#include <spawn.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <ostream>
#include <sstream>
#include <streambuf>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "campaign/case_run.h"
#include "campaign/cases.h"
#include "campaign/spec.h"
#include "cli/mission_run.h"
#include "core/file.h"
#include "vehicle/params.h"

extern char** environ;

namespace {

using Clock = std::chrono::steady_clock;

constexpr const char* kSpec = STRATA_SOURCE_DIR "/missions/tank/campaign.toml";
constexpr const char* kTankMission = STRATA_SOURCE_DIR "/missions/tank/tank.coral";
constexpr int kInProcessRuns = 40;

// Starts argv with stdout and stderr to /dev/null: its pid, or -1.
pid_t start(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  argv.reserve(args.size() + 1);
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  pid_t pid = -1;
  const int spawned = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  return spawned == 0 ? pid : -1;
}

// Whether pid exited 0. (`strata campaign` exits 1 when a case fails an
// expectation; every case of the example passes, so anything else is a
// broken build or machine.)
bool exited_ok(pid_t pid) {
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return false;
  }
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

// Wall seconds of the whole campaign as one process with two workers, or
// a negative value.
double campaign_wall_s(const std::filesystem::path& dir) {
  const std::filesystem::path out = dir / "campaign";
  std::filesystem::remove_all(out);
  const auto t0 = Clock::now();
  const pid_t pid = start({STRATA_EXE, "campaign", kSpec, "--out", out.string(), "-j", "2", "-q"});
  if (pid < 0 || !exited_ok(pid)) return -1.0;
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Each case's `strata run` command line, its files written into dir.
std::vector<std::vector<std::string>> case_commands(const strata::campaign::Spec& spec,
                                                    const std::filesystem::path& dir) {
  namespace campaign = strata::campaign;
  std::vector<std::vector<std::string>> out;
  for (std::uint64_t i = 0; i < spec.case_count(); ++i) {
    const campaign::Case c = campaign::case_at(spec, i);
    const std::string scenario = (dir / fmt::format("case-{}.toml", i)).string();
    if (!strata::core::write_file_atomically(scenario, campaign::scenario_toml(spec, c)).ok()) return {};
    std::string params;
    if (!c.params.empty()) {
      params = (dir / fmt::format("case-{}.params.toml", i)).string();
      const auto text = strata::vehicle::params_toml(campaign::case_params(spec, c));
      if (!strata::core::write_file_atomically(params, text).ok()) return {};
    }
    std::vector<std::string> argv{STRATA_EXE};
    for (std::string& a : campaign::repro_run_args(spec, c, scenario, params)) argv.push_back(std::move(a));
    // No mission log: the campaign keeps a failing case's only, and every
    // case of the example passes.
    argv.emplace_back("--no-log");
    out.push_back(std::move(argv));
  }
  return out;
}

// Wall seconds of every case as its own process, two at a time, or a
// negative value.
double per_process_wall_s(const std::vector<std::vector<std::string>>& commands) {
  const auto t0 = Clock::now();
  std::vector<pid_t> running;
  bool ok = true;
  std::size_t next = 0;
  while ((next < commands.size() || !running.empty()) && ok) {
    while (running.size() < 2 && next < commands.size()) {
      const pid_t pid = start(commands[next++]);
      if (pid < 0) {
        ok = false;
        break;
      }
      running.push_back(pid);
    }
    int status = 0;
    const pid_t done = wait(&status);
    if (done < 0) {
      ok = errno == EINTR;
      continue;
    }
    std::erase(running, done);
    ok = WIFEXITED(status) && WEXITSTATUS(status) < 64;
  }
  for (pid_t pid : running) exited_ok(pid);
  if (!ok) return -1.0;
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

class NullBuf : public std::streambuf {
 protected:
  int_type overflow(int_type c) override { return traits_type::not_eof(c); }
  std::streamsize xsputn(const char*, std::streamsize n) override { return n; }
};

// The median wall seconds of one nominal tank run in this process with
// telemetry at hz, or a negative value.
double in_process_run_s(double hz) {
  NullBuf null;
  std::ostream out(&null);
  std::vector<double> runs;
  for (int i = 0; i < kInProcessRuns; ++i) {
    strata::cli::RunOptions o;
    o.mission = kTankMission;
    o.telemetry_hz = hz;
    std::ostringstream err;
    const auto t0 = Clock::now();
    const strata::cli::RunReport report = strata::cli::run_mission(o, out, err);
    runs.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
    if (report.exit_code != 0) return -1.0;
  }
  std::sort(runs.begin(), runs.end());
  return runs[runs.size() / 2];
}

// Wall seconds of every case of spec run in this process one after
// another, or a negative value when a case did not give its result line.
double cases_in_process_s(const strata::campaign::Spec& spec) {
  namespace campaign = strata::campaign;
  const campaign::CaseRunConfig config;  // no folder: nothing written
  const auto t0 = Clock::now();
  for (std::uint64_t i = 0; i < spec.case_count(); ++i) {
    const auto line = campaign::run_case(spec, campaign::case_at(spec, i), config);
    if (!line.contains("pass")) return -1.0;
  }
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

void bm_campaign(benchmark::State& st) {
  char tmpl[] = "/tmp/strata-campaign-bench-XXXXXX";
  if (mkdtemp(tmpl) == nullptr) {
    st.SkipWithError("no temporary folder");
    return;
  }
  const std::filesystem::path dir(tmpl);
  const auto spec = strata::campaign::load_spec(kSpec);
  const auto commands = spec ? case_commands(spec.value(), dir) : std::vector<std::vector<std::string>>{};
  const std::size_t cases = commands.size();
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  double campaign_s = 0, per_process_s = 0, in_process_s = 0, spec_hz_s = 0, cases_s = 0;
  for (auto _ : st) {
    campaign_s = campaign_wall_s(dir);
    per_process_s = cases > 0 ? per_process_wall_s(commands) : -1.0;
    in_process_s = in_process_run_s(strata::cli::RunOptions{}.telemetry_hz);
    spec_hz_s = spec ? in_process_run_s(spec.value().telemetry_hz) : -1.0;
    cases_s = spec ? cases_in_process_s(spec.value()) : -1.0;
    if (cases == 0 || campaign_s < 0 || per_process_s < 0 || in_process_s < 0 || spec_hz_s < 0 || cases_s < 0) break;
  }
  std::filesystem::remove_all(dir);
  if (cases == 0 || campaign_s < 0 || per_process_s < 0 || in_process_s < 0 || spec_hz_s < 0 || cases_s < 0) {
    st.SkipWithError(cases == 0          ? "the spec did not load or its files could not be written"
                     : campaign_s < 0    ? "the campaign did not exit 0"
                     : per_process_s < 0 ? "a case's strata run exited 64 or more"
                     : cases_s < 0       ? "a case run in this process gave no result"
                                         : "the in-process tank run did not complete");
    return;
  }
  const double n = static_cast<double>(cases);
  const double limit = cores / in_process_s;
  st.counters["cases"] = n;
  st.counters["campaign_cases_per_s"] = n / campaign_s;
  st.counters["per_process_cases_per_s"] = n / per_process_s;
  st.counters["campaign_over_per_process"] = per_process_s / campaign_s;
  st.counters["in_process_ms"] = in_process_s * 1000.0;
  st.counters["limit_cases_per_s"] = limit;
  st.counters["campaign_over_limit"] = n / campaign_s / limit;
  st.counters["in_process_spec_hz_ms"] = spec_hz_s * 1000.0;
  st.counters["campaign_over_spec_hz_limit"] = n / campaign_s / (cores / spec_hz_s);
  st.counters["cases_in_process_ms"] = cases_s / n * 1000.0;
  st.counters["campaign_over_cases_limit"] = cases_s / (cores * campaign_s);
}

}  // namespace

BENCHMARK(bm_campaign)->Name("campaign/tank")->UseRealTime()->Unit(benchmark::kMillisecond)->Iterations(1);

int main(int argc, char** argv) {
  // cases_in_process runs tank.pl here: this program is not beside the
  // precompiled PROLOG driver, as strata is.
  ::setenv("STRATA_PROLOG_DRIVER", STRATA_PRECOMPILED_DRIVER, 0);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
