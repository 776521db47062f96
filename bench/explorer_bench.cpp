// The reachability explorer (petri::explore) on nets with known state
// spaces, full exploration, no reductions, one thread.
//
//   explore/referendum/N      Referendum-N: 3^N + 1 states (N = 15: 14,348,908)
//   explore/philosophers/N    dining philosophers: 3^N states
//   explore/pnml/MODEL        a net of ../shared/pnml (Kanban-PT-00005,
//                             FMS-PT-00005, Referendum-PT-0015), when present
//
//   explore/pnml-nolive/MODEL the same with ExploreOptions::liveness = false
//
// Counters: states, edges, states_per_s (states over the wall time of one
// exploration, liveness pass included), bytes_per_state
// (ExploreResult::memory_bytes: the hash table holding the packed markings
// plus the breadth-first queue, over the states), peak_bytes_per_state
// (ExploreResult::peak_memory_bytes: the most those held at once, a growing
// table included, over the states). Targets (issue 6): Referendum-PT-0015
// >= 2 M states/s and <= 24 bytes/state; Kanban-PT-00005 >= 1.5 M states/s;
// FMS-PT-00005 >= 0.5 M states/s. The process's own peak (max RSS) is
// measured on `strata verify --pnml` (docs/verification.md).
#include <benchmark/benchmark.h>

#include <chrono>
#include <filesystem>
#include <string>

#include "petri/explorer.h"
#include "petri/net_families.h"
#include "petri/pnml.h"

namespace strata::petri {
namespace {

void report(benchmark::State& st, const ExploreResult& r, double seconds) {
  st.counters["states"] = static_cast<double>(r.states);
  st.counters["edges"] = static_cast<double>(r.edges);
  st.counters["states_per_s"] = seconds > 0 ? static_cast<double>(r.states) / seconds : 0;
  st.counters["bytes_per_state"] = r.states ? static_cast<double>(r.memory_bytes) / static_cast<double>(r.states) : 0;
  st.counters["peak_bytes_per_state"] =
      r.states ? static_cast<double>(r.peak_memory_bytes) / static_cast<double>(r.states) : 0;
  if (!r.complete) st.SkipWithError(r.stopped_why.c_str());
}

void run(benchmark::State& st, const Net& net, bool liveness = true) {
  ExploreResult r;
  double seconds = 0;
  ExploreOptions options;
  options.liveness = liveness;
  for (auto _ : st) {
    auto start = std::chrono::steady_clock::now();
    r = explore(net, options);
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    benchmark::DoNotOptimize(r.states);
  }
  report(st, r, seconds);
}

void bm_referendum(benchmark::State& st) { run(st, referendum(static_cast<unsigned>(st.range(0)))); }
void bm_philosophers(benchmark::State& st) { run(st, dining_philosophers(static_cast<unsigned>(st.range(0)))); }

void bm_pnml(benchmark::State& st, const std::string& model, bool liveness) {
  const std::string path = std::string(STRATA_SOURCE_DIR) + "/../shared/pnml/" + model + "/model.pnml";
  if (!std::filesystem::exists(path)) {
    st.SkipWithError("../shared/pnml not present");
    return;
  }
  auto net = read_pnml(path);
  if (!net) {
    st.SkipWithError(net.error().message.c_str());
    return;
  }
  run(st, net.value().net, liveness);
}

BENCHMARK(bm_referendum)->Name("explore/referendum")->Arg(10)->Arg(15)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(bm_philosophers)
    ->Name("explore/philosophers")
    ->Arg(10)
    ->Arg(13)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);
BENCHMARK_CAPTURE(bm_pnml, kanban, std::string("Kanban-PT-00005"), true)
    ->Name("explore/pnml/Kanban-PT-00005")
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);
BENCHMARK_CAPTURE(bm_pnml, fms, std::string("FMS-PT-00005"), true)
    ->Name("explore/pnml/FMS-PT-00005")
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);
BENCHMARK_CAPTURE(bm_pnml, referendum, std::string("Referendum-PT-0015"), true)
    ->Name("explore/pnml/Referendum-PT-0015")
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);
// The same without the liveness pass (ExploreOptions::liveness = false).
BENCHMARK_CAPTURE(bm_pnml, kanban_nolive, std::string("Kanban-PT-00005"), false)
    ->Name("explore/pnml-nolive/Kanban-PT-00005")
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);
BENCHMARK_CAPTURE(bm_pnml, fms_nolive, std::string("FMS-PT-00005"), false)
    ->Name("explore/pnml-nolive/FMS-PT-00005")
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

}  // namespace
}  // namespace strata::petri

BENCHMARK_MAIN();
