// The timing analysis checked against runs (issue 38): the tank and the
// guarded survey, a leak at times spread over the run, and each run's time
// from the leak to the first `exec surface` after it. A run later than the
// proven worst case shows the analysis unsound, and fails here. The
// campaign at size (1,000 cases) is bench/bound_bench.cpp.
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "cli/bound_check.h"
#include "support/tank_run.h"

namespace strata::cli {
namespace {

const std::string kMissions = std::string(STRATA_SOURCE_DIR) + "/missions/";

std::string text_of(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void cross_check(const std::string& mission, const std::string& scenario, const std::vector<double>& times,
                 std::size_t at_least_measured) {
  const coral::BoundQuery q = coral::parse_bound("fault system_problem -> exec surface").value();
  const coral::BoundAnswer proven = prove_bound(mission, q);
  ASSERT_EQ(coral::BoundAnswer::Verdict::Bounded, proven.verdict) << proven.message;
  run_testing::TempDir dir;
  const auto measured = measure_reactions(mission, q, "leak", times, scenario, dir.file(""));
  std::size_t counted = 0;
  double worst = 0;
  for (const auto& m : measured) {
    if (!m.reaction_s) continue;  // the leak came once the vehicle was already surfacing
    ++counted;
    worst = std::max(worst, *m.reaction_s);
    EXPECT_LE(*m.reaction_s, proven.worst_s + 1e-9)
        << fmt::format("a leak at {} s was answered {:.1f} s later, past the proven {:.1f} s: the analysis is unsound",
                       m.fault_s, *m.reaction_s, proven.worst_s);
  }
  EXPECT_GE(counted, at_least_measured);
  std::printf("[ figure ] %s: proven %.1f s, worst measured %.1f s over %zu leaks\n", mission.c_str(), proven.worst_s,
              worst, counted);
}

TEST(BoundCrossCheck, NoTankLeakIsAnsweredLaterThanTheProvenBound) {
  std::vector<double> times;
  for (int i = 0; i < 24; ++i) times.push_back(0.5 + 0.9 * i);  // over the dive and the hold
  cross_check(kMissions + "tank/tank.coral", "seed = 3\n", times, 12);
}

TEST(BoundCrossCheck, NoSurveyLeakIsAnsweredLaterThanTheProvenBound) {
  std::string world = text_of(kMissions + "survey/scenarios/nominal.toml");
  std::vector<double> times = {3.7, 401.55, 1333.3};  // the launch, a leg, the last leg
  cross_check(kMissions + "survey/survey.coral", world, times, 3);
}

}  // namespace
}  // namespace strata::cli
