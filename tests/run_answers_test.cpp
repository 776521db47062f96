// `strata run --answers FILE` (docs/verification.md, "Witnesses as runs"):
// a counterexample or a question's witness written by `strata verify
// --witness-out` runs down its own path, the log showing each scripted
// answer; a run that leaves the script stops (65) through the safe end; a
// bad answers file stops the run before anything moves.
#include "support/tank_run.h"

#include <chrono>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "cli/witness_out.h"
#include "core/test_fifo.h"
#include "coral/verifier.h"
#include "run/answers.h"
#include "run/coral_load.h"
#include "run/inputs.h"

namespace strata::cli::run_testing {
namespace {

const std::string kStuckMission = std::string(STRATA_SOURCE_DIR) + "/tests/verify/stuck_mission.coral";
const std::string kFilterOn = kTankDir + "/witnesses/filter_on.json";
const std::string kTankPl = kTankDir + "/tank.pl";

std::vector<json> events(const ParsedLog& log, const std::string& name) {
  std::vector<json> out;
  for (const auto& line : log.lines) {
    if (line.value("event", "") == name) out.push_back(line);
  }
  return out;
}

// The transitions of net `net` the log says fired, in order.
std::vector<std::string> fired_in(const ParsedLog& log, const std::string& net) {
  std::vector<std::string> out;
  for (const auto& f : events(log, "fire")) {
    if (f.at("net") == net) out.push_back(f.at("transition"));
  }
  return out;
}

void write(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

TEST(RunAnswers, AVerifyCounterexampleRunsDownItsPathInTheLog) {
  TempDir dir;
  // What `strata verify stuck_mission.coral --witness-out FILE` does.
  auto catalogue = run::load_catalogue_option("");
  ASSERT_TRUE(catalogue.ok());
  run::CoralLoad load = run::load_coral_file(kStuckMission, catalogue.value());
  ASSERT_TRUE(load.program) << load.diagnostics_json().dump();
  const coral::VerifyReport report = coral::verify_program(*load.program);
  const std::string witness = dir.file("stuck.json");
  ASSERT_EQ(0, write_report_witness(report, kStuckMission, "", witness));
  const json file = json::parse(read_file(witness));
  EXPECT_EQ("no_deadlock counterexample", file.at("from"));
  std::vector<std::string> path_fired;
  for (const auto& step : file.at("path")) {
    const std::string text = step.get<std::string>();
    const auto fire_at = text.find(". fire ");
    if (fire_at == std::string::npos) continue;
    const std::string rest = text.substr(fire_at + 7);
    path_fired.push_back(rest.substr(0, rest.find_first_of(": ")));
  }
  ASSERT_EQ((std::vector<std::string>{"read_setpoint", "wait_a_second", "check_depth"}), path_fired);

  RunOptions o;
  o.mission = kStuckMission;
  o.answers = witness;
  o.log = dir.file("run.jsonl");
  std::ostringstream out, err;
  RunReport r = run_mission(o, out, err);
  ASSERT_TRUE(r.result.has_value()) << err.str();
  EXPECT_EQ(1, r.exit_code);
  EXPECT_NE(std::string::npos, r.result->reason.find("mission stalled")) << r.result->reason;
  EXPECT_NE(std::string::npos, r.result->reason.find("not_reached:1")) << r.result->reason;
  EXPECT_EQ(3u, r.answers_used);
  EXPECT_EQ(3u, r.answers_total);
  const ParsedLog log = parse_log(read_file(o.log));
  // The run's firings in the phase are the witness's, in its order.
  EXPECT_EQ(path_fired, fired_in(log, "stuck_phase"));
  const auto scripted = events(log, "scripted_answer");
  ASSERT_EQ(3u, scripted.size());
  // No mission data was loaded and the network never started: the vehicle
  // refused the setpoint (0); the script's answer (1) is what the mission got.
  EXPECT_EQ("next_setpt_data", scripted[0].at("primitive"));
  EXPECT_EQ(0, scripted[0].at("vehicle"));
  EXPECT_EQ(1, scripted[0].at("answer"));
  EXPECT_EQ(6, scripted[2].at("step"));
  const auto header = events(log, "answers");
  ASSERT_EQ(1u, header.size());
  EXPECT_EQ(witness, header[0].at("file"));
  const auto end = events(log, "answers_end");
  ASSERT_EQ(1u, end.size());
  EXPECT_EQ(3, end[0].at("used"));
  EXPECT_EQ(3, end[0].at("of"));
  // The log still ends as every run's does.
  ASSERT_TRUE(log.mission_end.has_value());
  EXPECT_EQ(log.lines.size() - 1, *log.mission_end);
  EXPECT_NE(std::string::npos, err.str().find("to follow the answers of --answers")) << err.str();
}

// The vehicle says its depth filter is off (1); the witness has it say on
// (0): the mission takes filter_was_on, which no run of the tank mission
// takes otherwise, skips starting the filter, and the vehicle refuses to
// submerge. The safe end surfaces it.
TEST(RunAnswers, AQuestionWitnessTakesABranchTheVehicleNeverWould) {
  TempDir dir;
  RunOptions o;
  o.mission = kMission;
  o.answers = kFilterOn;
  o.log = dir.file("run.jsonl");
  std::ostringstream out, err;
  RunReport r = run_mission(o, out, err);
  ASSERT_TRUE(r.result.has_value()) << err.str();
  EXPECT_EQ(Outcome::Failed, r.result->outcome);
  EXPECT_NE(std::string::npos, r.result->reason.find("exec submerge was not executed")) << r.result->reason;
  const ParsedLog log = parse_log(read_file(o.log));
  const auto dive = fired_in(log, "dive_from_surface");
  ASSERT_GE(dive.size(), 3u);
  EXPECT_EQ((std::vector<std::string>{"read_setpoint", "check_filter", "filter_was_on"}),
            std::vector<std::string>(dive.begin(), dive.begin() + 3));
  const auto scripted = events(log, "scripted_answer");
  ASSERT_EQ(2u, scripted.size());
  EXPECT_EQ("depth_filter_off", scripted[1].at("primitive"));
  EXPECT_EQ(1, scripted[1].at("vehicle"));
  EXPECT_EQ(0, scripted[1].at("answer"));
  EXPECT_TRUE(r.emergency_shutdown);
  ASSERT_TRUE(r.final_depth_m.has_value());
  EXPECT_LE(*r.final_depth_m, vehicle::default_params().surface_depth_m);
}

// The mission net's witness for its abort exit says phase 4 ends at abort;
// the phase's own answers are not scripted, the vehicle's make it complete,
// and the run stops there: 65, stopped by "answers", surfaced, log closed.
TEST(RunAnswers, ARunThatLeavesTheScriptStopsWith65ThroughTheSafeEnd) {
  TempDir dir;
  const std::string answers = dir.file("abort.json");
  write(answers, R"({"strata_answers": 1, "answers": [
    {"net": "tank", "transition": "phase1", "action": "phase", "primitive": "initialize", "answer": "complete"},
    {"net": "tank", "transition": "phase2", "action": "phase", "primitive": "dive_from_surface", "answer": "abort"}]})");
  RunOptions o;
  o.mission = kMission;
  o.answers = answers;
  o.log = dir.file("run.jsonl");
  std::ostringstream out, err;
  RunReport r = run_mission(o, out, err);
  ASSERT_TRUE(r.result.has_value()) << err.str();
  EXPECT_EQ(65, r.exit_code);
  EXPECT_EQ("answers", r.stopped_by);
  EXPECT_EQ(1u, r.answers_used);
  EXPECT_NE(std::string::npos, r.answers_diverged.find("phase dive_from_surface (run by phase2 of tank) ended at "
                                                       "'complete', where the script has 'abort'"))
      << r.answers_diverged;
  ASSERT_TRUE(r.final_depth_m.has_value());
  EXPECT_LE(*r.final_depth_m, vehicle::default_params().surface_depth_m);
  const ParsedLog log = parse_log(read_file(o.log));
  ASSERT_TRUE(log.mission_end.has_value());
  EXPECT_EQ("answers", log.at(log.mission_end).at("stopped_by"));
  EXPECT_EQ(65, log.at(log.mission_end).at("exit_code"));
  EXPECT_EQ(1u, events(log, "answers_diverged").size());
  // It stopped at phase 2's end: no call of phase 3 reached the vehicle.
  EXPECT_FALSE(log.in_phase("dive_from_surface").empty());
  EXPECT_TRUE(log.in_phase("submerge_to_depth").empty());
}

// Entries naming no net answer the next call of their primitive, in CORAL
// and in PROLOG alike.
TEST(RunAnswers, AScriptWithoutNetsDrivesPrologRulesToo) {
  TempDir dir;
  RunOptions o;
  o.mission = kTankPl;
  o.answers = kTankDir + "/witnesses/system_problem.json";
  o.log = dir.file("run.jsonl");
  std::ostringstream out, err;
  RunReport r = run_mission(o, out, err);
  ASSERT_TRUE(r.result.has_value()) << err.str();
  EXPECT_EQ(Outcome::Aborted, r.result->outcome) << r.result->reason;
  EXPECT_EQ(1u, r.answers_used);
  const auto scripted = events(parse_log(read_file(o.log)), "scripted_answer");
  ASSERT_EQ(1u, scripted.size());
  EXPECT_EQ(0, scripted[0].at("vehicle"));
  EXPECT_EQ(1, scripted[0].at("answer"));
}

// Regression: the test above, after the studio's run of the same rules in
// one process of the test program, crashed inside SWI-Prolog: the studio's
// run had started it on the studio's PROLOG thread, and this one called it
// from the main thread (the studio's tests have a program of their own
// now). On one thread, as a campaign's worker runs its cases (rules kept
// between runs), the rules run plain, then driven by a script, then plain
// again, each ending as it does alone.
TEST(RunAnswers, PrologRunsOneAfterAnotherInOneProcessEachEndAsAlone) {
  auto run = [](const std::string& answers) {
    RunOptions o;
    o.mission = kTankPl;
    o.answers = answers;
    o.keep_mission = true;
    return run_logged(std::move(o));
  };
  auto expect_plain = [](const MissionRun& r, const char* which) {
    ASSERT_TRUE(r.report.result.has_value()) << which << " run: " << r.err;
    EXPECT_EQ(Outcome::Completed, r.report.result->outcome) << which << " run: " << r.report.result->reason;
    EXPECT_EQ(0u, r.report.answers_used) << which << " run";
  };
  expect_plain(run(""), "first");
  const MissionRun scripted = run(kTankDir + "/witnesses/system_problem.json");
  ASSERT_TRUE(scripted.report.result.has_value()) << scripted.err;
  EXPECT_EQ(Outcome::Aborted, scripted.report.result->outcome) << scripted.report.result->reason;
  EXPECT_EQ(1u, scripted.report.answers_used);
  EXPECT_EQ(1u, events(scripted.log, "scripted_answer").size());
  expect_plain(run(""), "third");
}

struct BadFile {
  std::string name, text;
  int exit_code;
  std::string message;
  std::string mission = kMission;
};

// Nothing moves: the vehicle is never started, and the run says where the
// file is wrong.
TEST(RunAnswers, ABadAnswersFileStopsTheRunBeforeAnythingMoves) {
  TempDir dir;
  const std::vector<BadFile> cases{
      {"malformed.json", "{\"strata_answers\": 1,\n  \"answers\": [ {\"action\": \"ask\" ,, ] }", 65,
       "malformed.json:2:34: not JSON"},
      {"unknown.json",
       R"({"strata_answers": 1, "answers": [{"action": "ask", "primitive": "depth_reachd", "answer": 0}]})", 65,
       "answers[0] (ask depth_reachd): unknown primitive 'depth_reachd' (did you mean 'depth_reached'?)"},
      {"kind.json", R"({"strata_answers": 1, "answers": [{"action": "ask", "primitive": "surface", "answer": 0}]})", 65,
       "'surface' is an exec primitive, not ask"},
      {"answer.json", R"({"strata_answers": 1, "answers": [{"action": "ask", "primitive": "time_out", "answer": 2}]})",
       65, "answers[0]: \"answer\": 2 is not 0 or 1"},
      {"transition.json",
       R"({"strata_answers": 1, "answers": [{"net": "dive_from_surface", "transition": "check_dpth",
           "action": "ask", "primitive": "depth_reached", "answer": 0}]})",
       65, "net 'dive_from_surface' has no transition 'check_dpth'"},
      {"action.json",
       R"({"strata_answers": 1, "answers": [{"net": "dive_from_surface", "transition": "check_time",
           "action": "ask", "primitive": "depth_reached", "answer": 0}]})",
       65, "transition 'check_time' of 'dive_from_surface' has no ask depth_reached action"},
      {"exit.json",
       R"({"strata_answers": 1, "answers": [{"net": "tank", "transition": "phase2",
           "action": "phase", "primitive": "dive_from_surface", "answer": "sideways"}]})",
       65, "phase 'dive_from_surface' has no exit 'sideways'"},
      {"version.json", R"({"strata_answers": 2, "answers": []})", 65, "a format this strata does not read"},
      {"key.json", R"({"strata_answers": 1, "answers": [], "extra": 1})", 65, "unknown key \"extra\""},
      {"big.json", std::string(run::kMaxAnswersFileBytes + 1, ' '), 65, "over the limit of 1048576 bytes"},
      {"prolog.json",
       R"({"strata_answers": 1, "answers": [{"net": "dive_from_surface", "transition": "check_depth",
           "action": "ask", "primitive": "depth_reached", "answer": 0}]})",
       65, "PROLOG rules have no nets", kTankPl},
  };
  for (const BadFile& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = dir.file(c.name);
    write(path, c.text);
    RunOptions o;
    o.mission = c.mission;
    o.answers = path;
    std::ostringstream out, err;
    RunReport r = run_mission(o, out, err);
    EXPECT_EQ(c.exit_code, r.exit_code) << err.str();
    EXPECT_FALSE(r.result.has_value());
    EXPECT_NE(std::string::npos, err.str().find(c.message)) << err.str();
    EXPECT_EQ(std::string::npos, out.str().find("vehicle phoenix")) << out.str();
  }
}

TEST(RunAnswers, AFifoOrAMissingFileIsRefusedAtOnce) {
  const auto fifo = core::testing::make_fifo("answers.json");
  ASSERT_FALSE(fifo.empty());
  for (const std::string& path : {fifo.string(), fifo.string() + ".missing"}) {
    RunOptions o;
    o.mission = kMission;
    o.answers = path;
    std::ostringstream out, err;
    const auto start = std::chrono::steady_clock::now();
    RunReport r = run_mission(o, out, err);
    EXPECT_LT(std::chrono::steady_clock::now() - start, 10s);
    EXPECT_EQ(74, r.exit_code) << err.str();
    EXPECT_NE(std::string::npos, err.str().find("strata run: --answers: ")) << err.str();
    EXPECT_FALSE(r.result.has_value());
  }
  std::filesystem::remove_all(fifo.parent_path());
}

}  // namespace
}  // namespace strata::cli::run_testing
