// Campaigns end to end, in this process: a few tank cases through the pool
// of worker processes, results.jsonl and the reports checked.
#include "campaign/campaign_run.h"

#include <algorithm>
#include <filesystem>
#include <sstream>

#include <signal.h>
#include <unistd.h>

#include <cerrno>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "campaign/campaign_test_support.h"
#include "campaign/cases.h"
#include "campaign/case_run.h"
#include "campaign/merge.h"
#include "campaign/output.h"
#include "campaign/pool.h"
#include "campaign/report_html.h"
#include "campaign/summary.h"

namespace strata::campaign {
namespace {

using testing::by_index;
using testing::TempDir;
namespace fs = std::filesystem;

// Six CORAL tank cases: nominal and a leak at 4 s and 14 s, two seeds each.
std::string small_spec(const std::string& nominal_expect) {
  return "name = \"small\"\nmissions = [\"" + testing::kTankDir + "/tank.coral\"]\nseeds = [1, 2]\n" + nominal_expect +
         R"(
[expect.leak]
outcomes = ["aborted"]
surface_within_s = 15
max_depth_m = 1.8
no_stall = true
[[family]]
fault = "none"
expect = "nominal"
[[family]]
fault = "leak"
at_s = [4, 14]
expect = "leak"
)";
}
const std::string kNominalOk =
    "[expect.nominal]\noutcomes = [\"completed\"]\nmax_depth_m = 1.8\nno_refused_exec = true\n";
const std::string kNominalTooDeep = "[expect.nominal]\noutcomes = [\"completed\"]\nmax_depth_m = 1.0\n";

Spec load(const TempDir& dir, const std::string& text) {
  auto spec = load_spec(dir.write("spec.toml", text));
  EXPECT_TRUE(spec.ok()) << spec.error().message;
  return spec.ok() ? std::move(spec).value() : Spec{};
}

std::vector<std::uint64_t> all(const Spec& spec) {
  std::vector<std::uint64_t> v(spec.case_count());
  for (std::uint64_t i = 0; i < v.size(); ++i) v[i] = i;
  return v;
}

CampaignOutcome run(const Spec& spec, const std::string& out, int jobs, double wall_limit_s = 120.0) {
  CampaignOptions o;
  o.out_dir = out;
  o.jobs = jobs;
  o.case_wall_limit_s = wall_limit_s;
  auto r = run_campaign(spec, all(spec), o);
  EXPECT_TRUE(r.ok()) << (r ? "" : r.error().message);
  return r ? r.value() : CampaignOutcome{};
}

TEST(CampaignRun, ASmallCampaignOnTwoWorkersWritesEveryCaseOnce) {
  TempDir dir;
  const Spec spec = load(dir, small_spec(kNominalOk));
  const CampaignOutcome out = run(spec, dir.file("out"), 2);
  EXPECT_EQ(6u, out.done);
  EXPECT_EQ(0u, out.failed);
  EXPECT_FALSE(out.interrupted);
  const auto lines = by_index(testing::read_results(dir.file("out/results.jsonl")));
  ASSERT_EQ(6u, lines.size());
  for (std::uint64_t i = 0; i < 6; ++i) {
    const auto& l = lines[i];
    EXPECT_EQ(i, l["index"].get<std::uint64_t>());
    EXPECT_TRUE(l["pass"].get<bool>()) << l.dump();
    EXPECT_EQ(i < 2 ? "none" : "leak", l["inputs"]["fault"]["kind"]);
    EXPECT_EQ(i < 2 ? "completed" : "aborted", l["outcome"]) << l.dump();
    if (i >= 2) {
      const double t = l["figures"]["time_to_surface_s"].get<double>();
      EXPECT_GE(t, 0.0);  // 0 when the vehicle was still at the surface at 4 s
      EXPECT_LE(t, 15.0);
    }
  }
  // Two workers shared the cases: results come from more than one process.
  const auto raw = testing::read_results(dir.file("out/results.jsonl"));
  std::set<long> pids;
  for (const auto& l : raw) pids.insert(l["timings"]["pid"].get<long>());
  EXPECT_EQ(2u, pids.size());
  EXPECT_TRUE(fs::is_empty(dir.file("out/logs"))) << "logs are kept for failing cases only";

  const auto report = nlohmann::json::parse(testing::read_text(dir.file("out/report.json")));
  EXPECT_EQ(6, report["cases"]["passed"]);
  EXPECT_EQ(4, report["matrix"][1]["cells"][0]["done"].get<int>() + report["matrix"][1]["cells"][1]["done"].get<int>());
  EXPECT_EQ(4u, report["time_to_surface"][0]["measured"].get<std::uint64_t>());
  EXPECT_TRUE(report["coverage"]["" + testing::kTankDir + "/tank.coral"]["never_fired"].is_array());
  const std::string html = testing::read_text(dir.file("out/report.html"));
  EXPECT_NE(std::string::npos, html.find("6 cases"));
  EXPECT_EQ(std::string::npos, html.find("http")) << "the report must not fetch anything";
  EXPECT_EQ(std::string::npos, html.find("<script"));
}

TEST(CampaignRun, TheSameSpecGivesTheSameResultsInOneProcessOrTwoWorkers) {
  TempDir dir;
  const Spec spec = load(dir, small_spec(kNominalOk));
  run(spec, dir.file("a"), 2);
  run(spec, dir.file("b"), 0);
  EXPECT_EQ(by_index(testing::read_results(dir.file("a/results.jsonl"))),
            by_index(testing::read_results(dir.file("b/results.jsonl"))));
}

// A worker keeps a PROLOG mission's rules loaded from one case to the next
// (strategic::KeepRules): what a case's rules asserted must not reach the next
// case. Here the leak cases' rules end in current_phase(mission_abort); run
// first, in the same process, they must leave the nominal cases completed.
TEST(CampaignRun, APrologCaseGivesTheSameResultWhateverItsWorkerRanBefore) {
  TempDir dir;
  std::string text = small_spec(kNominalOk);
  text.replace(text.find("tank.coral"), 10, "tank.pl");
  const Spec spec = load(dir, text);
  ASSERT_EQ(6u, spec.case_count());
  run(spec, dir.file("a"), 2);  // first: the pool forks before this process starts SWI-Prolog
  std::vector<std::uint64_t> leaks_first = all(spec);
  std::reverse(leaks_first.begin(), leaks_first.end());
  CampaignOptions o;
  o.out_dir = dir.file("b");
  o.jobs = 0;  // every case in this process, one after another
  ASSERT_TRUE(run_campaign(spec, leaks_first, o).ok());
  const auto a = by_index(testing::read_results(dir.file("a/results.jsonl")));
  const auto b = by_index(testing::read_results(dir.file("b/results.jsonl")));
  ASSERT_EQ(6u, b.size());
  for (std::uint64_t i = 0; i < 6; ++i) EXPECT_EQ(i < 2 ? "completed" : "aborted", b[i]["outcome"]) << b[i].dump();
  EXPECT_EQ(a, b);
}

TEST(CampaignRun, AFailingExpectationKeepsTheLogTheScenarioAndACommandThatReproducesIt) {
  TempDir dir;
  const Spec spec = load(dir, small_spec(kNominalTooDeep));
  const CampaignOutcome out = run(spec, dir.file("out"), 2);
  EXPECT_EQ(2u, out.failed) << "both nominal cases dive to 1.5 m, deeper than 1.0";
  for (const auto& l : testing::read_results(dir.file("out/results.jsonl"))) {
    if (l["pass"].get<bool>()) continue;
    const std::uint64_t i = l["index"].get<std::uint64_t>();
    EXPECT_EQ("strata campaign " + spec.path + " --case " + std::to_string(i), l["repro"]);
    const auto& depth = l["checks"][2];
    EXPECT_EQ("max_depth_m", depth["name"]);
    EXPECT_FALSE(depth["pass"].get<bool>());
    EXPECT_GT(depth["figure"].get<double>(), 1.4);
    EXPECT_TRUE(fs::is_regular_file(dir.file("out/" + l["log"].get<std::string>())));
    EXPECT_NE(std::string::npos,
              testing::read_text(dir.file("out/" + l["log"].get<std::string>())).find("mission_end"));
    // The scenario file is the case: it reads back as the same run.
    const std::string scenario = testing::read_text(dir.file("out/" + l["scenario"].get<std::string>()));
    EXPECT_EQ(scenario_toml(spec, case_at(spec, i)), scenario);
    // And the case run alone again fails the same way, with the same figure.
    const auto again = run_case(spec, case_at(spec, i), CaseRunConfig{"", KeepLogs::None, {}});
    EXPECT_FALSE(again["pass"].get<bool>());
    EXPECT_EQ(depth["figure"].get<double>(), again["checks"][2]["figure"].get<double>());
  }
  const auto report = nlohmann::json::parse(testing::read_text(dir.file("out/report.json")));
  ASSERT_EQ(2u, report["failures"].size());
  const std::string html = testing::read_text(dir.file("out/report.html"));
  EXPECT_NE(std::string::npos, html.find("--case 0"));
}

// A passing case runs without a mission log; a failing one whose log is
// kept runs again with it, and the log kept is of a run that went the same
// way as the one the line reports.
TEST(CampaignRun, AFailingCaseRunAgainForItsLogKeepsTheLogOfTheSameRun) {
  TempDir dir;
  const Spec spec = load(dir, small_spec(kNominalTooDeep));
  fs::create_directories(dir.file("out/logs"));
  fs::create_directories(dir.file("out/scenarios"));
  bool failed_one = false, passed_one = false;
  for (std::uint64_t i = 0; i < spec.case_count(); ++i) {
    int runs_again = 0;
    // A worker restarts the case's wall-clock limit there.
    const CaseRunConfig config{dir.file("out"), KeepLogs::Failed, [&] { ++runs_again; }};
    const auto line = run_case(spec, case_at(spec, i), config);
    const std::string log = dir.file(fmt::format("out/logs/case-{}.jsonl", i));
    EXPECT_FALSE(line.contains("log_note")) << line.dump();
    EXPECT_EQ(line["pass"].get<bool>() ? 0 : 1, runs_again) << line.dump();
    if (line["pass"].get<bool>()) {
      passed_one = true;
      EXPECT_FALSE(line.contains("log")) << line.dump();
      EXPECT_FALSE(fs::exists(log));
      continue;
    }
    failed_one = true;
    ASSERT_TRUE(line.contains("log")) << line.dump();
    std::istringstream lines(testing::read_text(log));
    nlohmann::json end;
    for (std::string l; std::getline(lines, l);) end = nlohmann::json::parse(l);
    ASSERT_EQ("mission_end", end["event"]) << end.dump();
    EXPECT_EQ(line["outcome"].get<std::string>(), end["outcome"].get<std::string>());
    EXPECT_NEAR(line["figures"]["sim_time_s"].get<double>(), end["sim_time"].get<double>(), 0.05);
  }
  EXPECT_TRUE(failed_one);
  EXPECT_TRUE(passed_one) << "the spec's fault cases pass";
}

// A failing case's second run, for its log, can go another way: here its
// mission's setpoints are edited in between (what a user editing a mission
// while its campaign runs does). The log kept is that run's, and log_note
// says so, in the line, report.json's failures and report.html.
TEST(CampaignRun, ACaseRunAgainThatGoesAnotherWayKeepsItsLogWithALogNoteInTheReports) {
  TempDir dir;
  fs::create_directories(dir.file("m"));
  for (const auto& e : fs::directory_iterator(testing::kTankDir)) {
    const std::string ext = e.path().extension().string();
    if (ext == ".coral" || ext == ".toml") fs::copy_file(e.path(), dir.file("m/" + e.path().filename().string()));
  }
  std::string spec_text = small_spec(kNominalTooDeep);
  spec_text.replace(spec_text.find(testing::kTankDir), testing::kTankDir.size(), dir.file("m"));
  const Spec spec = load(dir, spec_text);
  fs::create_directories(dir.file("out/logs"));
  fs::create_directories(dir.file("out/scenarios"));
  const std::string setpoints = testing::read_text(dir.file("m/setpoints.toml"));
  const std::string shallow = "depth_m = 0.8";
  ASSERT_NE(std::string::npos, setpoints.find("depth_m = 1.5"));
  const CaseRunConfig config{dir.file("out"), KeepLogs::Failed, [&] {
                               std::string edited = setpoints;
                               edited.replace(edited.find("depth_m = 1.5"), shallow.size(), shallow);
                               std::ofstream(dir.file("m/setpoints.toml"), std::ios::trunc) << edited;
                             }};
  const auto line = run_case(spec, case_at(spec, 0), config);  // nominal, seed 1: 1.5 m, deeper than 1.0
  EXPECT_FALSE(line["pass"].get<bool>()) << line.dump();
  ASSERT_TRUE(line.contains("log_note")) << line.dump();
  EXPECT_EQ("the log is of the case run again to write it, which went another way (completed)", line["log_note"]);
  ASSERT_TRUE(line.contains("log")) << line.dump();
  std::istringstream lines(testing::read_text(dir.file("out/" + line["log"].get<std::string>())));
  double deepest = 0.0;
  for (std::string l; std::getline(lines, l);) {
    const auto e = nlohmann::json::parse(l);
    if (e["event"] == "telemetry") deepest = std::max(deepest, e["depth_m"].get<double>());
  }
  EXPECT_LT(deepest, 1.0) << "the log is of the second run, to the edited 0.8 m";

  Summary summary(spec);
  summary.add(line);
  const auto report = summary.to_json(CampaignRun{1, 1, 0.0, false, "strata campaign spec.toml"});
  ASSERT_EQ(1u, report["failures"].size());
  EXPECT_EQ(line["log_note"], report["failures"][0]["log_note"]);
  EXPECT_NE(std::string::npos, report_html(report).find("which went another way (completed)"));
}

TEST(CampaignRun, ACaseOverItsWallTimeIsACrashedCaseAndTheCampaignGoesOn) {
  TempDir dir;
  const Spec spec = load(dir, small_spec(kNominalOk));
  // No tank case runs in a microsecond: every worker is killed in turn,
  // every case is reported, none is lost, and the campaign ends.
  const CampaignOutcome out = run(spec, dir.file("out"), 2, 1e-6);
  EXPECT_EQ(6u, out.done);
  const auto lines = testing::read_results(dir.file("out/results.jsonl"));
  ASSERT_EQ(6u, lines.size());
  std::set<std::uint64_t> seen;
  int crashed = 0;
  for (const auto& l : lines) {
    seen.insert(l["index"].get<std::uint64_t>());
    if (l["pass"].get<bool>()) continue;  // a case may finish before the parent looks
    ++crashed;
    EXPECT_EQ("crashed", l["outcome"]);
    EXPECT_NE(std::string::npos, l["reason"].get<std::string>().find("wall time for one case")) << l.dump();
    EXPECT_EQ("ran", l["checks"][0]["name"]);
  }
  EXPECT_EQ(6u, seen.size());
  EXPECT_GE(crashed, 1);
}

TEST(CampaignRun, CoverageNamesTheTransitionsNoCaseFired) {
  TempDir dir;
  // Nominal runs only: the mission completes, so its abort path never fires.
  const Spec spec = load(dir, "missions = [\"" + testing::kTankDir + "/tank.coral\"]\n[[family]]\nfault = \"none\"\n");
  run(spec, dir.file("out"), 0);
  const auto report = nlohmann::json::parse(testing::read_text(dir.file("out/report.json")));
  const auto& cov = report["coverage"][testing::kTankDir + "/tank.coral"];
  const auto never = cov["never_fired"].get<std::vector<std::string>>();
  EXPECT_NE(never.end(), std::find(never.begin(), never.end(), "tank.abort_mission"));
  EXPECT_EQ(never.end(), std::find(never.begin(), never.end(), "tank.shutdown"));
  EXPECT_EQ(1, cov["fired"]["tank.shutdown"].get<int>());
  EXPECT_EQ(cov["transitions"].get<std::size_t>(), cov["fired"].size() + never.size());
  EXPECT_EQ(1, cov["exits"]["tank.closed"].get<int>());
  EXPECT_FALSE(cov["exits"].contains("tank.closed_after_abort"));
}

TEST(CampaignRun, ShardsMergedGiveTheResultsAndReportOfOneRun) {
  TempDir dir;
  const Spec spec = load(dir, small_spec(kNominalTooDeep));  // two failing cases: their logs travel too
  run(spec, dir.file("whole"), 2);
  for (int shard = 0; shard < 3; ++shard) {
    auto picked = shard_indices(std::to_string(shard) + "/3", spec.case_count());
    ASSERT_TRUE(picked.ok());
    EXPECT_EQ(2u, picked.value().size());
    CampaignOptions o;
    o.out_dir = dir.file("shard" + std::to_string(shard));
    o.jobs = 1;
    ASSERT_TRUE(run_campaign(spec, picked.value(), o).ok());
  }
  auto merged =
      merge_campaigns(spec, {dir.file("shard0"), dir.file("shard1"), dir.file("shard2")}, dir.file("merged"), "test");
  ASSERT_TRUE(merged.ok()) << merged.error().message;
  EXPECT_EQ(6u, merged.value().done);
  EXPECT_EQ(2u, merged.value().failed);
  EXPECT_EQ(by_index(testing::read_results(dir.file("whole/results.jsonl"))),
            by_index(testing::read_results(dir.file("merged/results.jsonl"))));
  auto whole = nlohmann::json::parse(testing::read_text(dir.file("whole/report.json")));
  auto joined = nlohmann::json::parse(testing::read_text(dir.file("merged/report.json")));
  for (const char* key : {"cases", "outcomes", "families", "matrix", "time_to_surface", "coverage"}) {
    EXPECT_EQ(whole[key], joined[key]) << key;
  }
  for (const auto& l : testing::read_results(dir.file("merged/results.jsonl"))) {
    if (l.contains("log")) {
      EXPECT_TRUE(fs::is_regular_file(dir.file("merged/" + l["log"].get<std::string>())));
    }
  }
  EXPECT_FALSE(shard_indices("3/3", 6).ok());
  EXPECT_FALSE(shard_indices("1", 6).ok());
}

// Regression: the pool handing a list to a worker that had just died
// raised SIGPIPE, which ended a process that does not ignore it (this test
// program did, now and then, in the test below): the write is an error.
TEST(CampaignRun, AWriteToAWorkerThatDiedIsAnErrorNotASignal) {
  ASSERT_EQ(SIG_DFL, ::signal(SIGPIPE, SIG_DFL)) << "the test needs SIGPIPE's default action";
  int fds[2];
  ASSERT_EQ(0, ::pipe(fds));
  ::close(fds[0]);
  EXPECT_FALSE(write_all_fd(fds[1], "0 1 2\n"));
  EXPECT_EQ(EPIPE, errno);
  ::close(fds[1]);
  sigset_t pending;
  sigpending(&pending);
  EXPECT_EQ(0, sigismember(&pending, SIGPIPE)) << "no SIGPIPE left for the thread to take later";
}

TEST(CampaignRun, AWorkerKilledFromOutsideCostsAtMostItsCaseAndIsReplaced) {
  TempDir dir;
  const Spec spec = load(dir, small_spec(kNominalOk));
  // Six cases on two workers; the first worker to answer is killed (as the
  // OOM killer would) right after its first result.
  const std::vector<std::uint64_t> indices = all(spec);
  std::vector<nlohmann::ordered_json> lines;
  PoolOptions o;
  o.workers = 2;
  long killed = 0;
  o.on_result = [&](const nlohmann::ordered_json& line) {
    lines.push_back(line);
    if (killed == 0 && line["timings"].contains("pid")) {
      killed = line["timings"]["pid"].get<long>();
      ::kill(static_cast<pid_t>(killed), SIGKILL);
    }
  };
  const PoolOutcome out = run_pool(spec, indices, CaseRunConfig{}, o);
  EXPECT_EQ(6u, out.done) << "every case answered once, the killed worker's list run by others";
  ASSERT_EQ(6u, lines.size());
  std::set<long> pids;
  std::set<std::uint64_t> seen;
  for (const auto& l : lines) {
    seen.insert(l["index"].get<std::uint64_t>());
    if (l["outcome"] == "crashed") {
      EXPECT_NE(std::string::npos, l["reason"].get<std::string>().find("died: signal 9")) << l.dump();
    } else {
      pids.insert(l["timings"]["pid"].get<long>());
    }
  }
  EXPECT_EQ(6u, seen.size());
  EXPECT_GE(pids.size(), 2u);
}

// Issue 21: a perturbed case's log did not say which vehicle it ran.
TEST(CampaignRun, AKeptLogNamesTheParameterFileAndThePerturbedValues) {
  TempDir dir;
  dir.write("phoenix.toml", vehicle::params_toml(vehicle::default_params()));
  const Spec spec = load(dir, "missions = [\"" + testing::kTankDir + R"(/tank.coral"]
params = "phoenix.toml"
max_sim_time_s = 5
[expect.completes]
outcomes = ["completed"]   # 5 s is too short: it fails
[[family]]
fault = "none"
perturb = { hull.mass_kg = [175] }
[[family]]
name = "unperturbed"
fault = "none"
expect = "completes"
)");
  ASSERT_EQ(2u, spec.case_count());
  CaseRunConfig config;
  config.out_dir = dir.file("out");
  config.keep_logs = KeepLogs::All;
  std::filesystem::create_directories(dir.file("out/logs"));
  std::filesystem::create_directories(dir.file("out/scenarios"));
  const nlohmann::ordered_json line = run_case(spec, case_at(spec, 0), config);
  ASSERT_TRUE(line.contains("log")) << line.dump();
  std::istringstream log(testing::read_text(dir.file("out/" + line["log"].get<std::string>())));
  std::string first;
  std::getline(log, first);
  const auto header = nlohmann::json::parse(first);
  EXPECT_EQ(dir.file("phoenix.toml"), header["params"]) << first;
  EXPECT_EQ(64u, header["params_sha256"].get<std::string>().size()) << first;
  EXPECT_EQ(175.0, header["param_overrides"]["hull.mass_kg"]) << first;
  // A failing case that perturbs nothing is reproduced on the spec's vehicle.
  const nlohmann::ordered_json failed = run_case(spec, case_at(spec, 1), config);
  ASSERT_FALSE(failed["pass"].get<bool>()) << failed.dump();
  ASSERT_TRUE(failed.contains("repro_run")) << failed.dump();
  EXPECT_NE(std::string::npos, failed["repro_run"].get<std::string>().find(" --params " + dir.file("phoenix.toml")))
      << failed.dump();
}

TEST(CampaignRun, EachCaseRunsTheVehicleWithItsPerturbedParameters) {
  TempDir dir;
  // 60 N of buoyancy is more than the thrusters' 36 N: that vehicle cannot
  // dive, so its case cannot complete; the nominal one does. The failing
  // case's parameter file reproduces it through `strata run --params`.
  const Spec spec = load(dir, "missions = [\"" + testing::kTankDir + R"(/tank.coral"]
[expect.nominal]
outcomes = ["completed"]
[[family]]
fault = "none"
expect = "nominal"
perturb = { hull.buoyancy_n = [5, 60] }
)");
  ASSERT_EQ(2u, spec.case_count());
  run(spec, dir.file("a"), 2);
  const auto lines = by_index(testing::read_results(dir.file("a/results.jsonl")));
  ASSERT_EQ(2u, lines.size());
  EXPECT_EQ(5.0, lines[0]["inputs"]["params"]["hull.buoyancy_n"]);
  EXPECT_EQ("completed", lines[0]["outcome"]) << lines[0].dump();
  EXPECT_TRUE(lines[0]["pass"].get<bool>());
  EXPECT_EQ(60.0, lines[1]["inputs"]["params"]["hull.buoyancy_n"]);
  EXPECT_NE("completed", lines[1]["outcome"]) << lines[1].dump();
  EXPECT_LT(lines[1]["figures"]["max_depth_m"].get<double>(), 0.5) << "it never got down";
  ASSERT_TRUE(lines[1].contains("params_file")) << lines[1].dump();
  auto params = vehicle::parse_params(testing::read_text(dir.file("a/" + lines[1]["params_file"].get<std::string>())),
                                      "case.params.toml");
  ASSERT_TRUE(params.ok()) << params.error().message;
  EXPECT_EQ(60.0, params.value().buoyancy_n);
  EXPECT_EQ(case_params(spec, case_at(spec, 1)), params.value());
  for (const auto& raw : testing::read_results(dir.file("a/results.jsonl"))) {
    if (raw["index"] != 1) continue;
    EXPECT_NE(std::string::npos,
              raw["repro_run"].get<std::string>().find(" --params " + dir.file("a/scenarios/case-1.params.toml")));
  }
  // The same spec, the same results, in one process too.
  run(spec, dir.file("b"), 0);
  EXPECT_EQ(lines, by_index(testing::read_results(dir.file("b/results.jsonl"))));
}

TEST(CampaignRun, APerturbedSurfaceDepthIsTheOneTimeToSurfaceIsMeasuredAgainst) {
  TempDir dir;
  // The same leak at 14 s, with the surface counted from 0.15 m and from
  // 1.2 m: the vehicle is "at the surface" sooner with the deeper one.
  const Spec spec = load(dir, "missions = [\"" + testing::kTankDir + R"(/tank.coral"]
[[family]]
fault = "leak"
at_s = 14
perturb = { detection.surface_depth_m = [0.15, 1.2] }
)");
  run(spec, dir.file("out"), 0);
  const auto lines = by_index(testing::read_results(dir.file("out/results.jsonl")));
  ASSERT_EQ(2u, lines.size());
  const double shallow = lines[0]["figures"]["time_to_surface_s"].get<double>();
  const double deep = lines[1]["figures"]["time_to_surface_s"].get<double>();
  EXPECT_LT(deep, shallow) << lines[0].dump() << "\n" << lines[1].dump();
}

// Found by a 100,000-case run: the mission surfaces and shuts down the
// moment the vehicle answers surface_reached (by its depth filter's
// estimate, 0.149 m), and the run ends with the last depth-cell reading at
// 0.156 m: "never seen at the surface" was a noisy reading's verdict.
TEST(CampaignRun, TheSurfaceIsTheVehiclesOwnEstimateNotOneNoisyDepthReading) {
  TempDir dir;
  const Spec spec = load(dir, "missions = [\"" + testing::kTankDir + R"(/tank.coral"]
seeds = [585]
[expect.leak]
outcomes = ["aborted", "completed"]
surface_within_s = 15.0
[[family]]
fault = "leak"
at_s = 5
perturb = { hull.buoyancy_n = [9.447651], thrusters.max_n = [15] }
expect = "leak"
)");
  CampaignOptions o;
  o.out_dir = dir.file("out");
  o.keep_logs = KeepLogs::All;
  ASSERT_TRUE(run_campaign(spec, all(spec), o).ok());
  const auto lines = testing::read_results(dir.file("out/results.jsonl"));
  ASSERT_EQ(1u, lines.size());
  // The case as found: the last telemetry's reading over 0.15 m, the
  // vehicle's estimate under it.
  std::ifstream log(dir.file("out/logs/case-0.jsonl"));
  nlohmann::json last;
  for (std::string line; std::getline(log, line);) {
    auto j = nlohmann::json::parse(line, nullptr, false);
    if (!j.is_discarded() && j.value("event", "") == "telemetry") last = j;
  }
  ASSERT_TRUE(last.is_object()) << "no telemetry in the kept log";
  EXPECT_GT(last["depth_m"].get<double>(), 0.15) << last.dump();
  EXPECT_LE(last["filtered_depth_m"].get<double>(), 0.15) << last.dump();
  EXPECT_TRUE(lines[0]["pass"].get<bool>()) << lines[0].dump();
  EXPECT_EQ("telemetry", lines[0]["figures"]["surface_seen"]) << lines[0].dump();
  EXPECT_LE(lines[0]["figures"]["time_to_surface_s"].get<double>(), 15.0) << lines[0].dump();
}

TEST(CampaignRun, TheOutputFolderIsNeverALink) {
  TempDir dir;
  const Spec spec = load(dir, small_spec(kNominalOk));
  fs::create_directory(dir.file("real"));
  fs::create_directory_symlink(dir.file("real"), dir.file("link"));
  CampaignOptions o;
  o.out_dir = dir.file("link");
  auto r = run_campaign(spec, {0}, o);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(std::string::npos, r.error().message.find("a symbolic link; not writing through it"));
  EXPECT_TRUE(fs::is_empty(dir.file("real")));
  dir.write("real/notes.txt", "mine");
  o.out_dir = dir.file("real");
  auto r2 = run_campaign(spec, {0}, o);
  ASSERT_FALSE(r2.ok()) << "a folder with other files in it is not ours to fill";
  EXPECT_EQ("mine", testing::read_text(dir.file("real/notes.txt")));
}

// A bound in the spec: proven once before the workers fork (the parent's
// cases and the workers' agree), reported in report.json's "bounds" beside
// the longest measured time; a bound the analysis cannot prove fails its
// cases and says why.
TEST(CampaignRun, ABoundIsProvenCheckedAndReportedAndAnUnprovableOneFailsItsCases) {
  TempDir dir;
  const std::string families = "[[family]]\nfault = \"leak\"\nat_s = [4, 14]\nexpect = \"leak\"\n";
  const Spec spec = load(dir, "missions = [\"" + testing::kTankDir +
                                  "/tank.coral\"]\nseeds = [1]\n[expect.leak]\nbound = \"fault system_problem -> exec "
                                  "surface\"\n" +
                                  families);
  const CampaignOutcome out = run(spec, dir.file("out"), 2);
  EXPECT_EQ(0u, out.failed);
  EXPECT_EQ(0u, out.past_proven_bound);
  const auto report = nlohmann::json::parse(testing::read_text(dir.file("out/report.json")));
  ASSERT_EQ(1u, report["bounds"].size()) << report["bounds"].dump();
  const auto& b = report["bounds"][0];
  EXPECT_EQ("fault system_problem -> exec surface", b["bound"]);
  EXPECT_EQ(4.5, b["proven_s"].get<double>());
  EXPECT_EQ(2u, b["measured"].get<std::uint64_t>());
  EXPECT_LE(b["max_s"].get<double>(), 4.5);
  EXPECT_EQ(0u, b["exceeded"].get<std::uint64_t>());
  EXPECT_NE(std::string::npos, testing::read_text(dir.file("out/report.html")).find("Proven bounds"));

  // The tank never calls `exec calibrate`: nothing to bound.
  const Spec never = load(dir, "missions = [\"" + testing::kTankDir +
                                   "/tank.coral\"]\nseeds = [1]\n[expect.leak]\nbound = \"fault system_problem -> exec "
                                   "calibrate\"\n" +
                                   families);
  const CampaignOutcome failed = run(never, dir.file("out2"), 0);
  EXPECT_EQ(2u, failed.failed);
  const auto lines = testing::read_results(dir.file("out2/results.jsonl"));
  ASSERT_EQ(2u, lines.size());
  for (const auto& l : lines) {
    bool seen = false;
    for (const auto& c : l["checks"]) {
      if (c["name"] != "bound") continue;
      seen = true;
      EXPECT_FALSE(c["pass"].get<bool>());
      EXPECT_EQ(0u, c.value("note", "").find("no proven bound: ")) << c.dump();
    }
    EXPECT_TRUE(seen) << l.dump();
  }
}

}  // namespace
}  // namespace strata::campaign
