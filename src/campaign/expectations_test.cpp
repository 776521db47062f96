// Expectations: each check's verdict, figure and note.
#include "campaign/expectations.h"

#include <functional>

#include <gtest/gtest.h>

#include "campaign/campaign_test_support.h"
#include "campaign/case_run.h"
#include "campaign/cases.h"

namespace strata::campaign {
namespace {

ExpectationSet all_checks() {
  ExpectationSet e;
  e.name = "all";
  e.outcomes = {"aborted"};
  e.surface_within_s = 10.0;
  e.max_depth_m = 1.0;
  e.no_stall = true;
  e.no_refused_exec = true;
  return e;
}

Observation aborted_after_leak() {
  Observation o;
  o.outcome = "aborted";
  o.sim_time_s = 20.0;
  o.max_depth_m = 0.8;
  o.fault_at_s = 5.0;
  o.fault_reached = true;
  o.time_to_surface_s = 4.0;
  o.surface_seen = "telemetry";
  return o;
}

std::string verdicts(const std::vector<Check>& checks) {
  std::string s;
  for (const Check& c : checks) s += (s.empty() ? "" : " ") + c.name + (c.pass ? ":pass" : ":FAIL");
  return s;
}

TEST(CampaignExpectations, EveryCheckPassesForAGoodRunAndKeepsItsFigure) {
  const auto checks = evaluate(all_checks(), aborted_after_leak());
  EXPECT_EQ("ran:pass outcome:pass surface_within_s:pass max_depth_m:pass no_stall:pass no_refused_exec:pass",
            verdicts(checks));
  EXPECT_EQ(4.0, checks[2].figure.get<double>());
  EXPECT_EQ(10.0, checks[2].limit.get<double>());
  EXPECT_EQ(0.8, checks[3].figure.get<double>());
}

// Each limit broken alone fails its own check and no other (issue 39: the
// test broke all five at once, so a check that failed for another's reason
// would have passed).
TEST(CampaignExpectations, EachLimitFailsOnItsOwn) {
  const std::vector<std::pair<std::string, std::function<void(Observation&)>>> breaks = {
      {"outcome", [](Observation& o) { o.outcome = "completed"; }},
      {"surface_within_s", [](Observation& o) { o.time_to_surface_s = 12.5; }},
      {"max_depth_m", [](Observation& o) { o.max_depth_m = 1.2; }},
      {"no_stall", [](Observation& o) { o.stalled = true; }},
      {"no_refused_exec",
       [](Observation& o) {
         o.refused_execs = 2;
         o.first_refused = "exec submerge at 3.0 s: answered 0";
       }},
  };
  for (const auto& [name, broken] : breaks) {
    SCOPED_TRACE(name);
    Observation o = aborted_after_leak();
    broken(o);
    std::string expected;
    for (const char* check : {"ran", "outcome", "surface_within_s", "max_depth_m", "no_stall", "no_refused_exec"}) {
      expected += (expected.empty() ? "" : " ") + std::string(check) + (name == check ? ":FAIL" : ":pass");
    }
    const auto checks = evaluate(all_checks(), o);
    EXPECT_EQ(expected, verdicts(checks));
    if (name == "no_refused_exec") {
      EXPECT_EQ(2, checks[5].figure.get<int>());
      EXPECT_EQ("exec submerge at 3.0 s: answered 0", checks[5].note);
    }
  }
}

TEST(CampaignExpectations, SurfacingIsJudgedOnlyWhenTheFaultHappened) {
  Observation o = aborted_after_leak();
  o.fault_reached = false;  // the run ended first
  o.time_to_surface_s.reset();
  auto checks = evaluate(all_checks(), o);
  EXPECT_TRUE(checks[2].pass);
  EXPECT_TRUE(checks[2].figure.is_null());
  EXPECT_EQ("the run ended (20.0 s) before the fault", checks[2].note);
  o.fault_reached = true;  // it happened, and the vehicle was never seen at the surface
  checks = evaluate(all_checks(), o);
  EXPECT_FALSE(checks[2].pass);
  EXPECT_EQ("the vehicle was not seen at the surface after the fault", checks[2].note);
  o.time_to_surface_s = 9.0;
  o.surface_seen = "final state";
  checks = evaluate(all_checks(), o);
  EXPECT_TRUE(checks[2].pass);
  EXPECT_NE(std::string::npos, checks[2].note.find("at most"));
}

TEST(CampaignExpectations, ARunThatNeverStartedFailsRanAndNothingElse) {
  Observation o;
  o.outcome = "error";
  o.reason = "tank.coral:3:1: error: ...";
  const auto checks = evaluate(all_checks(), o);
  EXPECT_EQ("ran:FAIL", verdicts(checks));
  EXPECT_EQ("tank.coral:3:1: error: ...", checks[0].note);
}

TEST(CampaignExpectations, AnExecTheVehicleAnswersZeroIsCountedInARealRun) {
  testing::TempDir dir;
  const std::string spec_path = dir.write(
      "spec.toml", "missions = [\"" + std::string(STRATA_SOURCE_DIR) +
                       "/src/campaign/testdata/exec_too_soon.coral\"]\n[expect.strict]\nno_refused_exec = true\n"
                       "[[family]]\nfault = \"none\"\nexpect = \"strict\"\n");
  auto spec = load_spec(spec_path);
  ASSERT_TRUE(spec.ok()) << spec.error().message;
  const auto line = run_case(spec.value(), case_at(spec.value(), 0), CaseRunConfig{"", KeepLogs::None, {}});
  EXPECT_FALSE(line["pass"].get<bool>()) << line.dump();
  const auto& check = line["checks"][1];
  EXPECT_EQ("no_refused_exec", check["name"]);
  EXPECT_EQ(1, check["figure"].get<int>());
  EXPECT_NE(std::string::npos, check["note"].get<std::string>().find("exec start_depth_filter at 0.1 s: answered 0"))
      << check.dump();
}

ExpectationSet bound_set() {
  ExpectationSet e;
  e.name = "leak";
  e.bound = coral::parse_bound("fault system_problem -> exec surface").value();
  return e;
}

BoundProof proof_of(double worst_s) {
  BoundProof p;
  p.worst_s = worst_s;
  return p;
}

TEST(CampaignExpectations, ABoundPassesWithinTheProofAndFailsTheAnalysisPastIt) {
  Observation o = aborted_after_leak();
  o.bound_to_at_s = 7.5;  // 2.5 s after the fault at 5 s
  const BoundProof proof = proof_of(4.5);
  auto checks = evaluate(bound_set(), o, &proof);
  ASSERT_EQ("ran:pass bound:pass", verdicts(checks));
  EXPECT_EQ(2.5, checks[1].figure.get<double>());
  EXPECT_EQ(4.5, checks[1].limit.get<double>());
  o.bound_to_at_s = 10.0;
  checks = evaluate(bound_set(), o, &proof);
  ASSERT_EQ("ran:pass bound:FAIL", verdicts(checks));
  EXPECT_EQ(
      "exec surface came 5.0 s after the fault, past the proven worst case of 4.5 s: the timing analysis is unsound",
      checks[1].note);
}

TEST(CampaignExpectations, ABoundWithoutItsEndIsJudgedByHowLongTheRunWentOn) {
  Observation o = aborted_after_leak();  // fault at 5 s, the run ends at 20 s
  BoundProof proof = proof_of(4.5);
  auto checks = evaluate(bound_set(), o, &proof);
  ASSERT_EQ("ran:pass bound:FAIL", verdicts(checks));
  EXPECT_NE(std::string::npos, checks[1].note.find("no exec surface in the 15.0 s the run went on")) << checks[1].note;
  o.bound_to_before_s = 4.0;  // already surfacing
  checks = evaluate(bound_set(), o, &proof);
  EXPECT_EQ("ran:pass bound:pass", verdicts(checks));
  EXPECT_NE(std::string::npos, checks[1].note.find("before the fault")) << checks[1].note;
  o.bound_to_before_s.reset();
  o.sim_time_s = 8.0;  // ended 3 s after the fault, within the proof
  EXPECT_EQ("ran:pass bound:pass", verdicts(evaluate(bound_set(), o, &proof)));
  o.sim_time_s = 20.0;
  proof.ends_without = true;  // the analysis knows a run may end without it
  EXPECT_EQ("ran:pass bound:pass", verdicts(evaluate(bound_set(), o, &proof)));
}

TEST(CampaignExpectations, ABoundWithoutAProofFailsAndPrologIsOnlyMeasured) {
  Observation o = aborted_after_leak();
  o.bound_to_at_s = 6.0;
  BoundProof unbounded;
  unbounded.why = "unbounded";
  auto checks = evaluate(bound_set(), o, &unbounded);
  ASSERT_EQ("ran:pass bound:FAIL", verdicts(checks));
  EXPECT_EQ("no proven bound: unbounded", checks[1].note);
  BoundProof prolog;
  prolog.measured_only = true;
  prolog.why = "PROLOG rules: no timing analysis, the time is only measured";
  checks = evaluate(bound_set(), o, &prolog);
  ASSERT_EQ("ran:pass bound:pass", verdicts(checks));
  EXPECT_EQ(1.0, checks[1].figure.get<double>());
  EXPECT_TRUE(checks[1].limit.is_null());
}

}  // namespace
}  // namespace strata::campaign
