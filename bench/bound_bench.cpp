// The timing analysis (issue 38's targets): the proven worst case from a
// leak to `exec surface` for the tank and the guarded survey, its cost, and
// a campaign of runs with the leak at times spread over the mission, each
// measuring the time from the leak to the first `exec surface` after it.
//
//   bound/prove/tank, bound/prove/survey     the analysis alone, per run
//   bound/campaign/tank     1,000 leaks, spread over the first 25 s
//   bound/campaign/survey     200 leaks, spread over 1,580 s
//
// Counters: proven_s (the worst case), measured_max_s (the campaign's),
// ratio = proven / measured (target at most 1.5), over_bound (runs later
// than proven: the analysis unsound if ever above 0), measured (runs with an
// `exec surface` after the leak).
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "cli/bound_check.h"

namespace strata::cli {
namespace {

const std::string kMissions = std::string(STRATA_SOURCE_DIR) + "/missions/";
const coral::BoundQuery kLeak = coral::parse_bound("fault system_problem -> exec surface").value();

void bm_prove(benchmark::State& st, const std::string& mission) {
  double proven = 0;
  for (auto _ : st) {
    const coral::BoundAnswer a = prove_bound(kMissions + mission, kLeak);
    if (a.verdict != coral::BoundAnswer::Verdict::Bounded) {
      st.SkipWithError(a.message.c_str());
      return;
    }
    proven = a.worst_s;
    st.counters["states"] = static_cast<double>(a.states);
  }
  st.counters["proven_s"] = proven;
}

void bm_campaign(benchmark::State& st, const std::string& mission, const std::string& world, double span_s, int cases) {
  const coral::BoundAnswer proven = prove_bound(kMissions + mission, kLeak);
  if (proven.verdict != coral::BoundAnswer::Verdict::Bounded) {
    st.SkipWithError(proven.message.c_str());
    return;
  }
  std::string world_text = "seed = 5\n";  // the survey's world brings its own
  if (!world.empty()) {
    std::ifstream in(kMissions + world);
    std::stringstream s;
    s << in.rdbuf();
    world_text = s.str();
  }

  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / fmt::format("strata_bound_bench_{}", ::getpid());
  std::filesystem::create_directories(dir);
  std::vector<double> times;
  for (int i = 0; i < cases; ++i) times.push_back(0.05 + span_s * static_cast<double>(i) / cases);
  std::vector<MeasuredReaction> measured;
  for (auto _ : st) measured = measure_reactions(kMissions + mission, kLeak, "leak", times, world_text, dir.string());
  std::error_code ignored;
  std::filesystem::remove_all(dir, ignored);
  double worst = 0;
  double counted = 0, over = 0;
  for (const auto& m : measured) {
    if (!m.reaction_s) continue;
    ++counted;
    worst = std::max(worst, *m.reaction_s);
    if (*m.reaction_s > proven.worst_s + 1e-9) ++over;
  }
  st.counters["proven_s"] = proven.worst_s;
  st.counters["measured_max_s"] = worst;
  st.counters["ratio"] = worst > 0 ? proven.worst_s / worst : 0.0;
  st.counters["over_bound"] = over;
  st.counters["measured"] = counted;
}

BENCHMARK_CAPTURE(bm_prove, tank, std::string("tank/tank.coral"))
    ->Name("bound/prove/tank")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(bm_prove, survey, std::string("survey/survey.coral"))
    ->Name("bound/prove/survey")
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);
BENCHMARK_CAPTURE(bm_campaign, tank, std::string("tank/tank.coral"), std::string(""), 25.0, 1000)
    ->Name("bound/campaign/tank")
    ->Iterations(1)
    ->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(bm_campaign, survey, std::string("survey/survey.coral"), std::string("survey/scenarios/nominal.toml"),
                  1580.0, 200)
    ->Name("bound/campaign/survey")
    ->Iterations(1)
    ->Unit(benchmark::kSecond);

}  // namespace
}  // namespace strata::cli

BENCHMARK_MAIN();
