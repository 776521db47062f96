// Verifier witnesses as campaign cases: a family's `answers` (docs/campaigns.md,
// "Witnesses as cases"), its `missions`, and the check every such case gets.
#include <algorithm>
#include <filesystem>

#include <gtest/gtest.h>

#include "campaign/campaign_run.h"
#include "campaign/campaign_test_support.h"
#include "campaign/cases.h"
#include "campaign/spec.h"

namespace strata::campaign {
namespace {

using testing::by_index;
using testing::TempDir;
namespace fs = std::filesystem;

const std::string kWitnessSpec = testing::kTankDir + "/witnesses/campaign.toml";

CampaignOutcome run_all(const Spec& spec, const std::string& out, int jobs) {
  std::vector<std::uint64_t> all(spec.case_count());
  for (std::uint64_t i = 0; i < all.size(); ++i) all[i] = i;
  CampaignOptions o;
  o.out_dir = out;
  o.jobs = jobs;
  auto r = run_campaign(spec, all, o);
  EXPECT_TRUE(r.ok()) << (r ? "" : r.error().message);
  return r ? r.value() : CampaignOutcome{};
}

const nlohmann::json* check(const nlohmann::json& line, const std::string& name) {
  for (const auto& c : line["checks"]) {
    if (c["name"] == name) return &c;
  }
  return nullptr;
}

TEST(CampaignWitness, AFamilyKeptToOneMissionCountsForItAlone) {
  auto spec = load_spec(kWitnessSpec);
  ASSERT_TRUE(spec.ok()) << spec.error().message;
  const Spec& s = spec.value();
  // tank.coral: nominal, filter_on, dive_abort, system_problem; tank.pl: nominal, system_problem.
  ASSERT_EQ(6u, s.case_count());
  const std::vector<std::pair<std::size_t, std::string>> expected{{0, "nominal"},    {0, "filter_on"},
                                                                  {0, "dive_abort"}, {0, "system_problem"},
                                                                  {1, "nominal"},    {1, "system_problem"}};
  for (std::uint64_t i = 0; i < s.case_count(); ++i) {
    const Case c = case_at(s, i);
    EXPECT_EQ(expected[i].first, c.mission) << i;
    EXPECT_EQ(expected[i].second, s.families[c.family].name) << i;
  }
  EXPECT_EQ("filter_on.json", case_inputs(s, case_at(s, 1))["answers"]);
  EXPECT_FALSE(case_inputs(s, case_at(s, 0)).contains("answers"));
}

TEST(CampaignWitness, WitnessCasesRunDownTheirPathsTheSameWayTwice) {
  TempDir dir;
  auto spec = load_spec(kWitnessSpec);
  ASSERT_TRUE(spec.ok()) << spec.error().message;
  const CampaignOutcome out = run_all(spec.value(), dir.file("a"), 2);
  EXPECT_EQ(6u, out.done);
  EXPECT_EQ(0u, out.failed);
  const auto lines = by_index(testing::read_results(dir.file("a/results.jsonl")));
  ASSERT_EQ(6u, lines.size());
  for (const auto& l : lines) EXPECT_TRUE(l["pass"].get<bool>()) << l.dump();
  // filter_on: the branch no run of the tank mission takes by itself.
  const auto& filter_on = lines[1];
  EXPECT_EQ("failed", filter_on["outcome"]);
  const auto fired = filter_on["coverage"]["fired"];
  EXPECT_NE(fired.end(), std::find(fired.begin(), fired.end(), "dive_from_surface.filter_was_on")) << fired.dump();
  const nlohmann::json* followed = check(filter_on, "answers_followed");
  ASSERT_NE(nullptr, followed);
  EXPECT_EQ(2, (*followed)["figure"]);
  EXPECT_EQ(2, (*followed)["limit"]);
  EXPECT_EQ(nullptr, check(lines[0], "answers_followed")) << "a case without answers has no such check";
  EXPECT_EQ("aborted", lines[2]["outcome"]);
  EXPECT_EQ("aborted", lines[5]["outcome"]) << "PROLOG rules follow a script without nets";
  // In one process this time: the same results.
  run_all(spec.value(), dir.file("b"), 0);
  EXPECT_EQ(lines, by_index(testing::read_results(dir.file("b/results.jsonl"))));
}

TEST(CampaignWitness, ACaseThatLeavesItsScriptFailsAnswersFollowed) {
  TempDir dir;
  const std::string answers = dir.write("abort.json", R"({"strata_answers": 1, "answers": [
    {"net": "tank", "transition": "phase2", "action": "phase", "primitive": "dive_from_surface", "answer": "abort"}]})");
  const std::string spec_path = dir.write("spec.toml", "missions = [\"" + testing::kTankDir + "/tank.coral\"]\n" +
                                                           R"([[family]]
name = "phase2_aborts"
fault = "none"
answers = "abort.json"
)");
  auto spec = load_spec(spec_path);
  ASSERT_TRUE(spec.ok()) << spec.error().message;
  const CampaignOutcome out = run_all(spec.value(), dir.file("out"), 0);
  EXPECT_EQ(1u, out.failed);
  const auto lines = testing::read_results(dir.file("out/results.jsonl"));
  ASSERT_EQ(1u, lines.size());
  const nlohmann::json* followed = check(lines[0], "answers_followed");
  ASSERT_NE(nullptr, followed);
  EXPECT_FALSE((*followed)["pass"].get<bool>());
  EXPECT_NE(std::string::npos, (*followed)["note"].get<std::string>().find("ended at 'complete'")) << lines[0].dump();
  EXPECT_NE(std::string::npos, lines[0]["repro_run"].get<std::string>().find("--answers " + answers));
}

// Regression: no_refused_exec counted the EXECs the vehicle answered 0, not
// those the scripted answers failed while the vehicle did them, so a
// witness's failing EXEC passed the check.
TEST(CampaignWitness, AnExecTheScriptFailsIsARefusedExec) {
  TempDir dir;
  dir.write("no_filter.json", R"({"strata_answers": 1, "answers": [
    {"action": "exec", "primitive": "start_depth_filter", "answer": 0}]})");
  const std::string spec_path = dir.write("spec.toml", "missions = [\"" + testing::kTankDir + "/tank.coral\", \"" +
                                                           testing::kTankDir + "/tank.pl\"]\n" +
                                                           R"([expect.clean]
no_refused_exec = true
[[family]]
name = "nominal"
fault = "none"
expect = "clean"
[[family]]
name = "no_filter"
fault = "none"
answers = "no_filter.json"
expect = "clean"
)");
  auto spec = load_spec(spec_path);
  ASSERT_TRUE(spec.ok()) << spec.error().message;
  run_all(spec.value(), dir.file("out"), 0);
  const auto lines = by_index(testing::read_results(dir.file("out/results.jsonl")));
  ASSERT_EQ(4u, lines.size());
  for (std::size_t i : {0u, 2u}) {
    const nlohmann::json* refused = check(lines[i], "no_refused_exec");
    ASSERT_NE(nullptr, refused);
    EXPECT_TRUE((*refused)["pass"].get<bool>()) << "the nominal run: " << lines[i].dump();
    EXPECT_EQ(0, lines[i]["figures"]["refused_execs"]);
  }
  for (std::size_t i : {1u, 3u}) {
    const nlohmann::json* refused = check(lines[i], "no_refused_exec");
    ASSERT_NE(nullptr, refused);
    EXPECT_FALSE((*refused)["pass"].get<bool>()) << lines[i].dump();
    EXPECT_EQ(1, (*refused)["figure"]) << lines[i].dump();
    EXPECT_EQ(1, lines[i]["figures"]["refused_execs"]);
    EXPECT_NE(std::string::npos, (*refused)["note"].get<std::string>().find(
                                     "exec start_depth_filter at 0.5 s: the script answered 0 (answers[0])"))
        << lines[i].dump();
  }
}

TEST(CampaignWitness, BadAnswersAreErrorsOfTheSpecWithTheirPlace) {
  TempDir dir;
  const std::string tank = "missions = [\"" + testing::kTankDir + "/tank.coral\", \"" + testing::kTankDir +
                           "/tank.pl\"]\n[[family]]\nfault = \"none\"\n";
  auto error_of = [&](const std::string& family) {
    auto spec = parse_spec(tank + family, dir.file("c.toml"));
    EXPECT_FALSE(spec.ok()) << family;
    return spec ? std::string() : spec.error().message;
  };
  dir.write("bad.json", "{ \"strata_answers\": 1, \"answers\": [ }");
  EXPECT_NE(std::string::npos, error_of("answers = \"bad.json\"").find("c.toml:4:11: answers 'bad.json': "))
      << error_of("answers = \"bad.json\"");
  EXPECT_NE(std::string::npos, error_of("answers = \"bad.json\"").find("not JSON"));
  EXPECT_NE(std::string::npos, error_of("answers = \"none.json\"").find("c.toml:4:11: answers 'none.json': "));
  dir.write("nets.json", R"({"strata_answers": 1, "answers": [{"net": "dive_from_surface", "transition": "check_depth",
    "action": "ask", "primitive": "depth_reached", "answer": 0}]})");
  EXPECT_NE(std::string::npos, error_of("answers = \"nets.json\"").find("(PROLOG rules): give the family missions"));
  EXPECT_NE(std::string::npos, error_of("missions = [\"tank.coral\"]")
                                   .find("c.toml:4:13: a family's mission must be one of the spec's 'missions'"));
  auto ok = parse_spec(tank + "answers = \"nets.json\"\nmissions = [\"" + testing::kTankDir + "/tank.coral\"]\n",
                       dir.file("c.toml"));
  EXPECT_TRUE(ok.ok()) << ok.error().message;
}

}  // namespace
}  // namespace strata::campaign
