// The timing analysis checked against runs (issue 38), through the
// campaigns users run: the tank campaign's and the survey leak sweep's
// `bound`, the leak to `exec surface`. A case later than the proven worst
// case fails its "bound" check: the analysis would be unsound. The campaign
// at size (1,000 cases) is bench/bound_bench.cpp.
#include <cstdio>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "campaign/case_run.h"
#include "campaign/cases.h"
#include "campaign/spec.h"

namespace strata::campaign {
namespace {

const std::string kMissions = std::string(STRATA_SOURCE_DIR) + "/missions/";

// Runs the spec's cases of `family` for `mission` whose fault starts at one of
// `at` (every time when empty) and the first seed; checks every one's "bound".
void cross_check(const std::string& spec_path, const std::string& mission, const std::string& family,
                 const std::vector<double>& at, std::size_t at_least_measured) {
  auto loaded = load_spec(spec_path);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  const Spec& spec = loaded.value();
  std::size_t ran = 0, measured = 0;
  double worst = 0, proven = 0;
  for (std::uint64_t i = 0; i < spec.case_count(); ++i) {
    const Case c = case_at(spec, i);
    if (spec.missions[c.mission].path != mission || spec.families[c.family].name != family) continue;
    if (c.seed != spec.seeds.front() || !c.fault) continue;
    if (!at.empty() && std::find(at.begin(), at.end(), c.fault->at_s) == at.end()) continue;
    const nlohmann::ordered_json line = run_case(spec, c, {});
    ++ran;
    const nlohmann::ordered_json* bound = nullptr;
    for (const auto& check : line["checks"]) {
      if (check["name"] == "bound") bound = &check;
    }
    ASSERT_NE(nullptr, bound) << line.dump();
    ASSERT_TRUE(bound->contains("limit") && (*bound)["limit"].is_number()) << "no proven bound: " << bound->dump();
    proven = (*bound)["limit"].get<double>();
    EXPECT_TRUE((*bound)["pass"].get<bool>()) << fmt::format("a leak at {} s: {}", c.fault->at_s, bound->dump());
    if ((*bound)["figure"].is_number()) {
      ++measured;
      worst = std::max(worst, (*bound)["figure"].get<double>());
    }
  }
  EXPECT_GT(ran, 0u);
  EXPECT_GE(measured, at_least_measured);
  EXPECT_LE(worst, proven);
  std::printf("[ figure ] %s: proven %.1f s, worst measured %.1f s over %zu leaks (%zu cases)\n", mission.c_str(),
              proven, worst, measured, ran);
}

TEST(BoundCrossCheck, NoTankLeakIsAnsweredLaterThanTheProvenBound) {
  cross_check(kMissions + "tank/campaign.toml", "tank.coral", "leak", {}, 15);
}

TEST(BoundCrossCheck, NoSurveyLeakIsAnsweredLaterThanTheProvenBound) {
  // The launch, a leg, the last leg.
  cross_check(kMissions + "survey/leak_sweep.toml", "survey.coral", "leak", {5, 400, 1330}, 3);
}

TEST(BoundCrossCheck, PrologRulesAreMeasuredButNotJudged) {
  auto loaded = load_spec(kMissions + "tank/campaign.toml");
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  const Spec& spec = loaded.value();
  for (std::uint64_t i = 0; i < spec.case_count(); ++i) {
    const Case c = case_at(spec, i);
    if (spec.missions[c.mission].path != "tank.pl" || spec.families[c.family].name != "leak") continue;
    if (!c.fault || c.fault->at_s != 5.0) continue;
    const nlohmann::ordered_json line = run_case(spec, c, {});
    for (const auto& check : line["checks"]) {
      if (check["name"] != "bound") continue;
      EXPECT_TRUE(check["pass"].get<bool>());
      EXPECT_FALSE(check.contains("limit")) << check.dump();
      EXPECT_TRUE(check["figure"].is_number()) << check.dump();
      EXPECT_NE(std::string::npos, check.value("note", "").find("PROLOG")) << check.dump();
      return;
    }
    FAIL() << "no bound check: " << line.dump();
  }
  FAIL() << "no tank.pl leak case at 5 s";
}

}  // namespace
}  // namespace strata::campaign
