// What the PROLOG Strategic level costs (issue 5): a primitive call on the
// Prolog side alone, and the nominal tank mission run end to end in both
// languages (missions/tank/tank.coral and tank.pl: the same primitive calls).
//
//   prolog/foreign_call
//     Rules written to a temp folder and loaded (strategic::PrologMission::load) at
//     setup, outside the timing:
//       mission :- between(1, 100000, _), exec_start_timer(X), X == 1, fail.
//       mission.
//     One iteration runs a strategic::PrologMissionQuery on them to the end, with a
//     Host whose answer() is 1 at once: no vehicle, no event loop. Counter
//     ns_per_call is steady_clock time over the iterations / primitive calls
//     (items_per_second says the same). Nothing is subtracted: a call
//     includes the wrapper exec_start_timer/1 -> call_primitive/3 with its
//     inference-limit re-arm, '$strata_call'/3's first call (arguments read,
//     Host::primitive) and yield, the resume with Host::answer() and the
//     unification, the loop's own between/3, ==/2 and fail, and, once per
//     100000 calls, opening and closing the query. An upper bound of the
//     overhead. Target: <= 1 us per call.
//
//   prolog/foreign_call/executor
//     The same rules through strategic::PrologExecutor, over a Tactics that
//     answers each call (value 1) from a handler posted to an asio
//     io_context: adds the executor's bookkeeping (action ids, catalogue
//     look-ups, events for no observers) and one post and dispatch per call.
//
//   prolog/load/tank
//     strategic::PrologMission::load of missions/tank/tank.pl (its rules, phase2.pl,
//     the primitives' module and the check) and the Mission's destruction:
//     the part of a PROLOG run that CORAL's load and compile replace.
//
//   run/tank/coral, run/tank/prolog
//     One whole nominal run through strata::cli::run_mission (embedded
//     vehicle in lockstep, default RunOptions), console to a stream that
//     discards it, as run_bench. Counters: ms_per_run (mean of
//     RunReport::wall_time_s), x_real_time (sum sim_time_s / sum
//     wall_time_s), calls_per_run (RunReport::primitive_calls).
//     Each does one untimed warm-up run first. The first PROLOG run in the
//     process also pays SWI-Prolog's one-time start (initialise, loading
//     driver.pl): it is made before anything else in this program touches
//     Prolog, by whichever prolog/ or run/tank/prolog benchmark comes first,
//     and its wall_time_s is reported as first_run_ms on run/tank/prolog.
//     The driver comes precompiled from the build folder
//     (STRATA_PROLOG_DRIVER, unless already set: "" for its text).
//     Target: PROLOG ms_per_run within 2x of CORAL's. Default RunOptions, as
//     the studio's runs: tank.pl's rules only declare predicates and load
//     files, so each run takes back the rules the one before loaded, put
//     back as they were after the load (RunOptions::reuse_rules,
//     strategic::KeepRules::Reproducible); the untimed warm-up run loads them.
//
//   run/tank/prolog/afresh
//     The same runs with RunOptions::reuse_rules off: each run loads and
//     checks the rules afresh, as the first run of a process does and every
//     run of rules whose directives compute; from the third load on, the
//     check is answered by the driver's memory of rules that passed it
//     (driver_check.pl), as it is for every load of a process but its first.
//
//   run/tank/prolog/kept
//     The same runs as a campaign's worker makes them (RunOptions::keep_mission):
//     the rules loaded once and taken back, put back as they were, for each
//     later run (strategic::KeepRules::Yes).
//
// A run or query that does not end as it should stops its benchmark with
// SkipWithError, so a broken run is never timed as a success.
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <asio.hpp>
#include <cstdlib>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <ostream>
#include <sstream>
#include <streambuf>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "cli/mission_run.h"
#include "core/diagnostic_printer.h"
#include "strategic/prolog_mission.h"
#include "strategic/prolog_executor.h"
#include "tactical/catalogue.h"

namespace strata {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr const char* kTankCoral = STRATA_SOURCE_DIR "/missions/tank/tank.coral";
constexpr const char* kTankProlog = STRATA_SOURCE_DIR "/missions/tank/tank.pl";
constexpr int kLoopCalls = 100'000;
constexpr std::uint64_t kInferenceLimit = 10'000'000;  // RunOptions' default

// Accepts and drops everything, as a console nobody reads.
class NullBuf : public std::streambuf {
 protected:
  int_type overflow(int_type c) override { return traits_type::not_eof(c); }
  std::streamsize xsputn(const char*, std::streamsize n) override { return n; }
};

// One run, console discarded; why says what went wrong when the exit code is not 0.
enum class Rules { Reused, Afresh, Kept };  // RunOptions::reuse_rules, its opposite, keep_mission

cli::RunReport run_once(const char* mission, std::string& why, Rules rules = Rules::Reused) {
  cli::RunOptions options;
  options.mission = mission;
  options.keep_mission = rules == Rules::Kept;
  options.reuse_rules = rules == Rules::Reused;
  NullBuf null;
  std::ostream out(&null);
  std::ostringstream err;  // empty in a nominal run
  cli::RunReport report = cli::run_mission(options, out, err);
  why = report.exit_code == 0 ? ""
                              : fmt::format("run_mission exit code {}: {}", report.exit_code, err.str().substr(0, 300));
  return report;
}

// The very first PROLOG run of the process, made once, before any other use
// of Prolog here. error is set when it failed.
struct FirstRun {
  double wall_s = 0.0;
  std::string error;
};
const FirstRun& first_prolog_run() {
  static const FirstRun first = [] {
    std::string why;
    cli::RunReport report = run_once(kTankProlog, why, Rules::Afresh);
    return FirstRun{report.wall_time_s, why.empty() ? "" : "first PROLOG run: " + why};
  }();
  return first;
}

// The loop's rules in a temp folder of their own, removed at the end.
class LoopRules {
 public:
  LoopRules() : dir_(fs::temp_directory_path() / fmt::format("strata_prolog_bench_{}", ::getpid())) {
    fs::create_directories(dir_);
    std::ofstream(dir_ / "loop.pl") << fmt::format(
        "mission :- between(1, {}, _), exec_start_timer(X), X == 1, fail.\nmission.\n", kLoopCalls);
  }
  ~LoopRules() {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }
  LoopRules(const LoopRules&) = delete;
  LoopRules& operator=(const LoopRules&) = delete;
  std::string path() const { return (dir_ / "loop.pl").string(); }

 private:
  fs::path dir_;
};

// Loads rules after the first PROLOG run, or says why not.
std::unique_ptr<strategic::PrologMission> load(const std::string& path, benchmark::State& st) {
  std::string why = first_prolog_run().error;
  core::SourceManager sources;
  core::DiagnosticSink sink;
  if (why.empty()) {
    auto mission = strategic::PrologMission::load(path, tactical::Catalogue::builtin(), sources, sink);
    if (mission) return std::move(mission.value());
    why = mission.error().message;
  }
  std::ostringstream text;
  core::print_diagnostics(text, sources, sink.diagnostics());
  if (!text.str().empty()) why += "\n" + text.str();
  st.SkipWithError(why.c_str());
  return nullptr;
}

void bm_load_tank(benchmark::State& st) {
  if (!load(kTankProlog, st)) return;  // and the first PROLOG run, untimed
  for (auto _ : st) {
    if (!load(kTankProlog, st)) break;
  }
}

// Answers every call with 1 at once and counts them.
class ImmediateHost final : public strategic::PrologHost {
 public:
  std::int64_t calls = 0;
  void primitive(const std::string&, std::vector<tactical::Value>) override { ++calls; }
  std::optional<int> answer() override { return 1; }
  void report(const std::string&, std::vector<tactical::Value>) override {}
  void phase_started(const std::string&) override {}
  void phase_ended(const std::string&, const std::string&) override {}
};

void set_per_call(benchmark::State& st, Clock::duration spent, std::int64_t calls) {
  if (calls == 0) return;
  st.SetItemsProcessed(calls);
  st.counters["ns_per_call"] = std::chrono::duration<double, std::nano>(spent).count() / static_cast<double>(calls);
}

void bm_foreign_call(benchmark::State& st) {
  LoopRules rules;
  auto mission = load(rules.path(), st);
  if (!mission) return;
  ImmediateHost host;
  Clock::duration spent{};
  for (auto _ : st) {
    auto start = Clock::now();
    strategic::PrologMissionQuery query(*mission, host, kInferenceLimit);
    prolog::Query::Status s;
    while ((s = query.next()) == prolog::Query::Status::Yield) {}
    query.close();
    spent += Clock::now() - start;
    if (s != prolog::Query::Status::True && s != prolog::Query::Status::Last) {
      st.SkipWithError(fmt::format("mission/0 did not succeed: {}", query.exception_text()).c_str());
      break;
    }
  }
  set_per_call(st, spent, host.calls);
}

// Each call answered 1 by a handler posted to the io_context.
class PostedTactics final : public strategic::Tactics {
 public:
  explicit PostedTactics(asio::io_context& io) : io_(io) {}
  std::int64_t calls = 0;
  void call(std::string_view, std::vector<tactical::Value>, tactical::CallHandler done) override {
    ++calls;
    asio::post(io_, [done = std::move(done)] { done(tactical::CallOutcome{true, 0.0}); });
  }
  double sim_time_s() const override { return 0.0; }

 private:
  asio::io_context& io_;
};

void bm_foreign_call_executor(benchmark::State& st) {
  LoopRules rules;
  asio::io_context io;
  PostedTactics tactics(io);
  Clock::duration spent{};
  for (auto _ : st) {
    // Rules run once per load (prolog_executor.h): load outside the timing.
    st.PauseTiming();
    auto mission = load(rules.path(), st);
    st.ResumeTiming();
    if (!mission) return;
    auto start = Clock::now();
    strategic::PrologExecutor executor(*mission, tactics, tactical::Catalogue::builtin(),
                                       strategic::PrologOptions{kInferenceLimit});
    std::optional<strategic::MissionResult> result;
    executor.start([&](const strategic::MissionResult& r) { result = r; });
    io.run();
    io.restart();
    spent += Clock::now() - start;
    if (!result || result->outcome != strategic::Outcome::Completed) {
      st.SkipWithError(fmt::format("the mission did not complete: {}", result ? result->reason : "no end").c_str());
      break;
    }
  }
  set_per_call(st, spent, tactics.calls);
}

void bm_run(benchmark::State& st, const char* mission, bool prolog, Rules rules = Rules::Reused) {
  if (prolog && !first_prolog_run().error.empty()) {
    st.SkipWithError(first_prolog_run().error.c_str());
    return;
  }
  std::string why;
  if (run_once(mission, why, rules).exit_code != 0) {
    st.SkipWithError(why.c_str());
    return;
  }
  double sim_s = 0.0;
  double wall_s = 0.0;
  double calls = 0.0;
  std::int64_t runs = 0;
  for (auto _ : st) {
    cli::RunReport report = run_once(mission, why, rules);
    if (report.exit_code != 0) {
      st.SkipWithError(why.c_str());
      break;
    }
    sim_s += report.sim_time_s;
    wall_s += report.wall_time_s;
    calls += static_cast<double>(report.primitive_calls);
    ++runs;
  }
  if (runs == 0) return;
  st.counters["ms_per_run"] = wall_s * 1000.0 / static_cast<double>(runs);
  st.counters["x_real_time"] = wall_s > 0 ? sim_s / wall_s : 0.0;
  st.counters["calls_per_run"] = calls / static_cast<double>(runs);
  if (prolog) st.counters["first_run_ms"] = first_prolog_run().wall_s * 1000.0;
}

template <class F>
void add(const char* name, F f) {
  benchmark::RegisterBenchmark(name, f)->UseRealTime()->Unit(benchmark::kMillisecond);
}

void register_all() {
  add("prolog/foreign_call", bm_foreign_call);
  add("prolog/foreign_call/executor", bm_foreign_call_executor);
  add("prolog/load/tank", bm_load_tank);
  add("run/tank/coral", [](benchmark::State& st) { bm_run(st, kTankCoral, false); });
  add("run/tank/prolog", [](benchmark::State& st) { bm_run(st, kTankProlog, true); });
  add("run/tank/prolog/afresh", [](benchmark::State& st) { bm_run(st, kTankProlog, true, Rules::Afresh); });
  add("run/tank/prolog/kept", [](benchmark::State& st) { bm_run(st, kTankProlog, true, Rules::Kept); });
}

}  // namespace
}  // namespace strata

int main(int argc, char** argv) {
  // This program is not beside the precompiled driver, as strata is.
  ::setenv("STRATA_PROLOG_DRIVER", STRATA_PRECOMPILED_DRIVER, 0);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  strata::register_all();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
