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
// ratio = proven / measured (target at most 1.5), over_bound (cases whose
// "bound" check failed: the analysis unsound if ever above 0), measured
// (cases with an `exec surface` after the leak). The cases are a campaign's
// (campaign::run_case), with the spec's `bound`.
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "campaign/bound.h"
#include "campaign/case_run.h"
#include "campaign/cases.h"
#include "run/bound_options.h"
#include "run/coral_load.h"

namespace strata::campaign {
namespace {

const std::string kMissions = std::string(STRATA_SOURCE_DIR) + "/missions/";

// A campaign of `cases` leaks spread over span_s, its bound the leak to `exec
// surface`, in a spec of its own in the temp folder.
Spec leak_campaign(const std::string& mission, const std::string& world, double span_s, int cases) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / fmt::format("strata_bound_bench_{}", ::getpid());
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "leaks.toml").string();
  std::ofstream(path) << fmt::format(
      "missions = [\"{}\"]\nseeds = [5]\nmax_sim_time_s = 3000\n{}"
      "[expect.leak]\nbound = \"fault system_problem -> exec surface\"\n"
      "[[family]]\nfault = \"leak\"\nat_s = {{ from = 0.05, to = {}, step = {} }}\nexpect = \"leak\"\n",
      kMissions + mission, world.empty() ? "" : fmt::format("world = \"{}\"\n", kMissions + world),
      0.05 + span_s * (cases - 1) / cases, span_s / cases);
  auto spec = load_spec(path);
  std::error_code ignored;
  std::filesystem::remove_all(dir, ignored);
  if (!spec) throw std::runtime_error(spec.error().message);
  return std::move(spec).value();
}

const ExpectationSet& leak_set(const Spec& spec) { return spec.expectations.at("leak"); }

void bm_prove(benchmark::State& st, const std::string& mission) {
  double proven = 0;
  const Spec spec = leak_campaign(mission, "", 1.0, 1);
  const coral::BoundQuery& q = *leak_set(spec).bound;
  const tactical::Catalogue& cat = tactical::Catalogue::builtin();
  const run::CoralLoad load = run::load_coral_file(kMissions + mission, cat);
  if (!load.program) {
    st.SkipWithError("the mission does not compile");
    return;
  }
  for (auto _ : st) {
    const coral::BoundAnswer a = coral::analyse_bound(*load.program, q, run::bound_options(cat));
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
  const Spec spec = leak_campaign(mission, world, span_s, cases);
  const BoundProof proof = proven_bound(spec, 0, leak_set(spec), spec.base_params);
  if (!proof.worst_s) {
    st.SkipWithError(proof.why.c_str());
    return;
  }
  double worst = 0, counted = 0, over = 0;
  for (auto _ : st) {
    for (std::uint64_t i = 0; i < spec.case_count(); ++i) {
      const nlohmann::ordered_json line = run_case(spec, case_at(spec, i), {});
      for (const auto& check : line["checks"]) {
        if (check["name"] != "bound") continue;
        if (!check["pass"].get<bool>()) ++over;
        if (!check["figure"].is_number()) continue;
        ++counted;
        worst = std::max(worst, check["figure"].get<double>());
      }
    }
  }
  st.counters["cases"] = static_cast<double>(spec.case_count());
  st.counters["proven_s"] = *proof.worst_s;
  st.counters["measured_max_s"] = worst;
  st.counters["ratio"] = worst > 0 ? *proof.worst_s / worst : 0.0;
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
}  // namespace strata::campaign

BENCHMARK_MAIN();
