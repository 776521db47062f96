// Why a run cannot start is a value (run::Error): each stage before the
// mission returns a kind its caller switches on, the input it concerns and,
// for mission text, a place; the run library prints nothing. The CLI alone
// maps a kind to an exit code and a `strata run:` line.
#include "support/tank_run.h"

#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "cli/run_problems.h"
#include "core/exit_codes.h"
#include "run/session.h"
#include "studio/studio_runner.h"

namespace strata::cli::run_testing {
namespace {

const std::string kDoesNotCompile = std::string(STRATA_SOURCE_DIR) + "/tests/run/syntax_error.coral";
const std::string kFailsItsVerification = std::string(STRATA_SOURCE_DIR) + "/tests/verify/exits_together.coral";

run::RunReport run_without_a_log(RunOptions o) {
  o.log.clear();
  run::RunSession session(std::move(o));
  return session.run();
}

TEST(RunErrors, AMissionThatIsNeitherCoralNorPrologIsAUsageError) {
  RunOptions o;
  o.mission = kTankDir + "/tank.csv";
  const run::RunReport r = run_without_a_log(o);
  ASSERT_TRUE(r.error);
  EXPECT_FALSE(r.result);
  EXPECT_EQ(run::ErrorKind::Usage, r.error->kind);
  EXPECT_EQ(0, r.exit_code);  // the caller picks the code
  EXPECT_EQ(strata::kExitUsage, exit_code(*r.error));
}

TEST(RunErrors, AMissionFileThatIsNotThereIsUnreadable) {
  RunOptions o;
  o.mission = kTankDir + "/no_such_mission.coral";
  const run::RunReport r = run_without_a_log(o);
  ASSERT_TRUE(r.error);
  EXPECT_EQ(run::ErrorKind::Unreadable, r.error->kind);
  EXPECT_EQ(strata::kExitIo, exit_code(*r.error));
}

TEST(RunErrors, AMissionThatDoesNotCompileIsInvalidAtThePlaceOfItsFirstError) {
  RunOptions o;
  o.mission = kDoesNotCompile;
  run::RunSession session(o);
  const auto loaded = session.load();
  ASSERT_FALSE(loaded);
  EXPECT_EQ(run::ErrorKind::Invalid, loaded.error().kind);
  ASSERT_TRUE(loaded.error().place);
  EXPECT_EQ(kDoesNotCompile, loaded.error().place->file);
  EXPECT_EQ(5u, loaded.error().place->line);
  EXPECT_GT(loaded.error().place->column, 0u);
  // The diagnostics stay with the session for the caller's printer.
  EXPECT_FALSE(session.loaded().diagnostics.empty());
  // run() after a failed load() does not load again, and says the same.
  const run::RunReport r = session.run();
  ASSERT_TRUE(r.error);
  EXPECT_EQ(loaded.error().message, r.error->message);
  EXPECT_EQ(strata::kExitInvalid, exit_code(*r.error));
}

TEST(RunErrors, AMissionThatFailsVerificationIsItsOwnKind) {
  RunOptions o;
  o.mission = kFailsItsVerification;
  const run::RunReport r = run_without_a_log(o);
  ASSERT_TRUE(r.error);
  EXPECT_EQ(run::ErrorKind::FailsVerification, r.error->kind);
  EXPECT_EQ(strata::kExitInvalid, exit_code(*r.error));
}

TEST(RunErrors, AnAnswersFileThatIsNotThereNamesItsInput) {
  RunOptions o;
  o.mission = kMission;
  o.answers = kTankDir + "/no_such_answers.json";
  const run::RunReport r = run_without_a_log(o);
  ASSERT_TRUE(r.error);
  EXPECT_EQ(run::ErrorKind::Unreadable, r.error->kind);
  EXPECT_EQ("--answers", r.error->input);
  EXPECT_EQ("strata run: --answers: " + r.error->message, error_line("strata run", *r.error));
}

TEST(RunErrors, AVehicleAddressWithoutAPortIsAUsageErrorOfTheVehicleOption) {
  RunOptions o;
  o.mission = kMission;
  o.vehicle = "127.0.0.1:notaport";
  const run::RunReport r = run_without_a_log(o);
  ASSERT_TRUE(r.error);
  EXPECT_EQ(run::ErrorKind::Usage, r.error->kind);
  EXPECT_EQ("--vehicle", r.error->input);
}

TEST(RunErrors, AVehicleNobodyListensForIsUnavailable) {
  // A port just bound and closed again: nothing listens there.
  asio::io_context io;
  asio::ip::tcp::acceptor probe(io, asio::ip::tcp::endpoint(asio::ip::make_address("127.0.0.1"), 0));
  const auto port = probe.local_endpoint().port();
  probe.close();
  RunOptions o;
  o.mission = kMission;
  o.vehicle = "127.0.0.1:" + std::to_string(port);
  const run::RunReport r = run_without_a_log(o);
  ASSERT_TRUE(r.error);
  EXPECT_EQ(run::ErrorKind::VehicleUnavailable, r.error->kind);
  EXPECT_EQ(strata::kExitIo, exit_code(*r.error));
}

TEST(RunErrors, TheCliWordsAndCodesWhatTheRunReturns) {
  RunOptions o;
  o.mission = kFailsItsVerification;
  o.log.clear();
  std::ostringstream out, err;
  const RunReport r = run_mission(o, out, err);
  EXPECT_EQ(strata::kExitInvalid, r.exit_code);
  // The properties that do not hold first, then the one line that says why.
  const std::string text = err.str();
  const auto fail_at = text.find("FAIL  exits_exclusive");
  const auto line_at = text.find("strata run: " + kFailsItsVerification + " fails verification; not running");
  ASSERT_NE(std::string::npos, fail_at) << text;
  ASSERT_NE(std::string::npos, line_at) << text;
  EXPECT_LT(fail_at, line_at);
}

TEST(RunErrors, ASummaryAsJsonCarriesTheErrorAsAValue) {
  RunOptions o;
  o.mission = kDoesNotCompile;
  run::RunReport r = run_without_a_log(o);
  std::ostringstream err;
  print_run_errors(err, r);
  const json j = run::summary_json(r);
  EXPECT_FALSE(j.at("started").get<bool>());
  EXPECT_EQ(strata::kExitInvalid, j.at("exit_code").get<int>());
  EXPECT_EQ("invalid", j.at("error").at("kind"));
  EXPECT_EQ(5, j.at("error").at("place").at("line"));
}

TEST(RunErrors, TheStudioSaysWhyARunDidNotStartInItsOwnWords) {
  RunOptions o;
  o.mission = kDoesNotCompile;
  run::RunSession session(o);
  const auto loaded = session.load();
  ASSERT_FALSE(loaded);
  const std::string text = studio::not_started_text(session.loaded(), loaded.error());
  EXPECT_EQ(0u, text.find("the mission does not load: syntax_error.coral:5:")) << text;
  EXPECT_EQ(std::string::npos, text.find("strata run")) << text;
  EXPECT_EQ(std::string::npos, text.find("--")) << text;
}

}  // namespace
}  // namespace strata::cli::run_testing
