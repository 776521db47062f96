#include "strategic/prolog_mission.h"

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <mutex>
#include <thread>

#include <gtest/gtest.h>

#include "strategic/prolog_mission_test_support.h"

namespace strata::strategic {
namespace {

namespace fs = std::filesystem;
using prolog_mission_testing::PrologMissionTest;
using prolog_mission_testing::Reported;
using prolog_mission_testing::Rules;
using prolog_mission_testing::ScriptedHost;

TEST_F(PrologMissionTest, CallsYieldAndAnswersAreUnifiedAsIntegers) {
  auto m = load_ok(rules_.write("m.pl", R"(
:- dynamic seen/1.
mission :- exec_sleep(2, X), X == 1, ask_depth_reached(Y), Y == 0,
           ood('shutdown_network', Z), integer(Z), report('all done'), assertz(seen(ok)).
)"));
  ASSERT_TRUE(m);
  ScriptedHost host;
  host.answers = {1, 0, 1};
  PrologMissionQuery q(*m, host, 100000);
  EXPECT_EQ(prolog::Query::Status::Yield, q.next());
  EXPECT_EQ(prolog::Query::Status::Yield, q.next());
  EXPECT_EQ(prolog::Query::Status::Yield, q.next());
  auto s = q.next();
  EXPECT_TRUE(s == prolog::Query::Status::True || s == prolog::Query::Status::Last) << q.exception_text();
  q.close();
  EXPECT_EQ(
      (std::vector<std::string>{"call sleep 2", "call depth_reached", "call shutdown_network", "report all done"}),
      host.events);
  EXPECT_EQ(RulesOutcome::Completed, mission_outcome(*m).value());
}

// Regression: rules drawing random numbers (X is random(1000), which the
// sandbox allows) reported different numbers on every run of the same
// inputs: SWI-Prolog seeds its generator afresh in each process.
TEST_F(PrologMissionTest, RandomNumbersAreTheSameOnEveryRun) {
  const std::string path = rules_.write("r.pl",
                                        "mission :- X is random(1000000), report(X), "
                                        "Y is random_float, report(Y).\n");
  std::vector<std::vector<std::string>> runs;
  for (int i = 0; i < 2; ++i) {
    auto m = load_ok(path);
    ASSERT_TRUE(m);
    ScriptedHost host;
    PrologMissionQuery q(*m, host, 100000);
    auto s = run(q);
    EXPECT_TRUE(s == prolog::Query::Status::True || s == prolog::Query::Status::Last) << q.exception_text();
    q.close();
    ASSERT_EQ(2u, host.events.size());
    runs.push_back(host.events);
    // Whatever the process drew in between.
    ASSERT_TRUE(prolog::call_once("_ is random(1000)").ok());
  }
  EXPECT_EQ(runs[0], runs[1]);
}

// Regression: the flags the sandbox lets rules set (occurs_check,
// double_quotes, ...) and a lowered stack limit are the process's: one run
// setting them changed how every later mission of the process (a campaign's
// worker, the studio) loaded and ran.
TEST_F(PrologMissionTest, FlagsARunSetsDoNotReachTheNextMission) {
  const std::string setter = rules_.write("set.pl",
                                          "mission :- set_prolog_flag(occurs_check, true), "
                                          "set_prolog_flag(double_quotes, atom), "
                                          "set_prolog_stack(global, limit(200000000)).\n");
  const std::string reader = rules_.write("read.pl",
                                          "mission :- current_prolog_flag(occurs_check, O), report(O), "
                                          "X = \"ab\", ( string(X) -> report(string) ; report(other) ), "
                                          "current_prolog_flag(stack_limit, L), "
                                          "( L > 200000000 -> report(stack_ok) ; report(stack_lowered) ).\n");
  auto run_events = [&](const std::string& path) {
    auto m = load_ok(path);
    EXPECT_TRUE(m);
    ScriptedHost host;
    if (!m) return host.events;
    PrologMissionQuery q(*m, host, 100000);
    auto s = run(q);
    EXPECT_TRUE(s == prolog::Query::Status::True || s == prolog::Query::Status::Last) << q.exception_text();
    q.close();
    return host.events;
  };
  const auto before = run_events(reader);
  ASSERT_EQ((std::vector<std::string>{"report false", "report string", "report stack_ok"}), before);
  run_events(setter);
  EXPECT_EQ(before, run_events(reader));
  // And the host's own queries after the run see them as before too.
  EXPECT_TRUE(prolog::call_once("current_prolog_flag(occurs_check, false)").value());
}

// Regression: rules loaded on a thread other than the one SWI-Prolog was
// started on crashed the process inside SWI-Prolog (a test program ran the
// studio's PROLOG run, on the studio's thread, then rules on its main
// thread). The load says why it cannot run there; the engine's thread is
// untouched.
TEST_F(PrologMissionTest, RulesLoadedOffSwiPrologsThreadAreAnErrorNotACrash) {
  const std::string path = rules_.write("m.pl", "mission :- report(ok).\n");
  ASSERT_TRUE(load_ok(path));
  std::string elsewhere;
  std::thread([&] {
    Reported reported;
    auto m = PrologMission::load(path, tactical::Catalogue::builtin(), reported.sources, reported.sink);
    elsewhere = m ? std::string("loaded") : m.error().message;
  }).join();
  EXPECT_NE(std::string::npos, elsewhere.find("started on another thread")) << elsewhere;
  EXPECT_TRUE(load_ok(path));
}

TEST_F(PrologMissionTest, Figure10StyleBoundVariableIsCheckedAfterTheCall) {
  // exec_submerge(X) with X already 1: the call is still made; 0 then fails.
  auto m = load_ok(rules_.write("m.pl", R"(
mission :- exec_start_timer(X), ( exec_submerge(X) -> report(ok) ; report(refused) ).
)"));
  ASSERT_TRUE(m);
  ScriptedHost host;
  host.answers = {1, 0};
  PrologMissionQuery q(*m, host, 100000);
  run(q);
  EXPECT_EQ((std::vector<std::string>{"call start_timer", "call submerge", "report refused"}), host.events);
}

TEST_F(PrologMissionTest, PhasesAreReportedWithTheirExit) {
  auto m = load_ok(rules_.write("m.pl", R"(
:- dynamic current_phase/1, complete/1, abort/1.
current_phase(1).
mission :- repeat, step, current_phase(mission_abort), !.
step :- current_phase(P), execute_phase(P), !, next_phase(P), !.
execute_phase(1) :- exec_start_timer(_), asserta(complete(1)).
execute_phase(2) :- ask_time_out(X), X = 1, asserta(abort(2)).
next_phase(1) :- retract(current_phase(1)), asserta(current_phase(2)).
next_phase(2) :- retract(current_phase(2)), asserta(current_phase(mission_abort)).
)"));
  ASSERT_TRUE(m);
  ScriptedHost host;
  PrologMissionQuery q(*m, host, 100000);
  auto s = run(q);
  ASSERT_NE(prolog::Query::Status::Exception, s) << q.exception_text();
  q.close();
  EXPECT_EQ((std::vector<std::string>{"phase 1", "call start_timer", "end 1 complete", "phase 2", "call time_out",
                                      "end 2 abort"}),
            host.events);
  EXPECT_EQ(RulesOutcome::Aborted, mission_outcome(*m).value());
}

TEST_F(PrologMissionTest, SyntaxErrorsHaveFileAndLine) {
  Reported messages;
  auto m = PrologMission::load(rules_.write("bad.pl", "mission :- exec_submerge(X.\nok.\n"),
                               tactical::Catalogue::builtin(), messages.sources, messages.sink);
  ASSERT_FALSE(m.ok());
  EXPECT_EQ(core::ErrorCode::InvalidInput, m.error().code);
  ASSERT_FALSE(messages.empty());
  EXPECT_EQ(core::Severity::Error, messages[0].severity);
  EXPECT_EQ(core::DiagnosticKind::PrologLoadError, messages[0].kind);
  EXPECT_NE(std::string::npos, messages.file(0).find("bad.pl")) << messages.headline(0);
  EXPECT_EQ(1u, messages.place(0).line) << messages.headline(0);
  EXPECT_EQ(core::Precision::Span, messages[0].precision) << messages.headline(0);
}

TEST_F(PrologMissionTest, UnknownPrimitivesAreFoundWhenTheRulesLoad) {
  Reported messages;
  auto m = PrologMission::load(rules_.write("m.pl",
                                            "mission :- start.\nstart :- exec_warp_drive(X), X = 1.\n"
                                            "start :- exec_sleep(1), ask_nothing(_).\n"),
                               tactical::Catalogue::builtin(), messages.sources, messages.sink);
  ASSERT_FALSE(m.ok());
  std::string all = messages.text();
  EXPECT_NE(std::string::npos, all.find("m.pl:2: error: exec_warp_drive/1: `warp_drive` is not an exec primitive"))
      << all;
  EXPECT_NE(std::string::npos, all.find("m.pl:3: error: exec_sleep/1: sleep takes 1 argument(s) here: use "
                                        "exec_sleep/2"))
      << all;
  EXPECT_NE(std::string::npos, all.find("ask_nothing/1: `nothing` is not an ask primitive")) << all;
}

// The sandbox checks every clause at once first (driver_check.pl): rules
// where two clauses among many safe ones are refused must still have each
// refusal placed at its own line, none hidden by the other or the rest.
TEST_F(PrologMissionTest, EveryRefusedClauseAmongSafeOnesIsPlacedAtItsLine) {
  std::string text = "mission :- step(1).\n";
  for (int i = 1; i <= 10; ++i) text += "step(" + std::to_string(i) + ") :- exec_sleep(1, _).\n";  // lines 2-11
  text += "clean :- shell('rm -rf /tmp/x').\n";                                                    // line 12
  for (int i = 1; i <= 5; ++i) text += "safe(" + std::to_string(i) + ") :- X is 1 + 2, X > 0.\n";  // 13-17
  text += "peek :- open('/etc/passwd', read, _).\n";                                               // line 18
  Reported messages;
  auto m =
      PrologMission::load(rules_.write("m.pl", text), tactical::Catalogue::builtin(), messages.sources, messages.sink);
  ASSERT_FALSE(m.ok());
  std::string all = messages.text();
  EXPECT_NE(std::string::npos, all.find("m.pl:12:")) << all;
  EXPECT_NE(std::string::npos, all.find("m.pl:18:")) << all;
  EXPECT_EQ(2u, messages.size()) << all;
}

TEST_F(PrologMissionTest, RulesWithoutMissionAreRefused) {
  Reported messages;
  auto m = PrologMission::load(rules_.write("m.pl", "go :- exec_submerge(_).\n"), tactical::Catalogue::builtin(),
                               messages.sources, messages.sink);
  ASSERT_FALSE(m.ok());
  ASSERT_EQ(1u, messages.size());
  EXPECT_NE(std::string::npos, messages[0].message.find("no mission/0")) << messages[0].message;
}

TEST_F(PrologMissionTest, AnUnreadableFileIsAnIoError) {
  Reported messages;
  auto m =
      PrologMission::load("/nonexistent/strata/m.pl", tactical::Catalogue::builtin(), messages.sources, messages.sink);
  ASSERT_FALSE(m.ok());
  EXPECT_EQ(core::ErrorCode::Io, m.error().code);
}

TEST_F(PrologMissionTest, LoopsWithoutPrimitivesHitTheInferenceLimit) {
  auto m = load_ok(rules_.write("m.pl", "mission :- exec_start_timer(_), spin.\nspin :- repeat, fail.\n"));
  ASSERT_TRUE(m);
  ScriptedHost host;
  PrologMissionQuery q(*m, host, 200000);
  EXPECT_EQ(prolog::Query::Status::Exception, run(q));
  EXPECT_TRUE(q.inference_limit_exceeded()) << q.exception_text();
  q.close();
  EXPECT_TRUE(prolog::call_once("between(1, 300000, _), fail ; true").value()) << "the limit is lifted after the run";
}

TEST_F(PrologMissionTest, TheLimitCountsBetweenCallsNotInTotal) {
  // 50 calls with 10k inferences of work each: 500k in all, under 100k per gap.
  auto m = load_ok(rules_.write("m.pl", R"(
mission :- between(1, 50, _), numlist(1, 3000, L), sum_list(L, _), exec_start_timer(_), fail.
mission.
)"));
  ASSERT_TRUE(m);
  ScriptedHost host;
  PrologMissionQuery q(*m, host, 100000);
  auto s = run(q);
  EXPECT_NE(prolog::Query::Status::Exception, s) << q.exception_text();
  EXPECT_EQ(50u, host.events.size());
}

TEST_F(PrologMissionTest, ACatchAllCannotSwallowTheLimitOrHalt) {
  // The "robust" idiom: each step in a catch-all, retried for ever.
  auto m = load_ok(rules_.write("m.pl",
                                "mission :- exec_start_timer(_), repeat, catch(step, _, fail), fail.\n"
                                "step :- spin.\nspin :- spin.\n"));
  ASSERT_TRUE(m);
  ScriptedHost host;
  PrologMissionQuery q(*m, host, 200000);
  EXPECT_EQ(prolog::Query::Status::Exception, run(q));
  EXPECT_TRUE(q.inference_limit_exceeded()) << q.exception_text();

  auto h = load_ok(rules_.write("h.pl", "mission :- catch(halt(4), _, true), exec_submerge(_).\n"));
  ASSERT_TRUE(h);
  ScriptedHost host2;
  PrologMissionQuery q2(*h, host2, 200000);
  EXPECT_EQ(prolog::Query::Status::Exception, run(q2));
  ASSERT_TRUE(q2.halted()) << q2.exception_text();
  EXPECT_EQ(4, *q2.halted());
  EXPECT_TRUE(host2.events.empty()) << "nothing runs after halt";
}

TEST_F(PrologMissionTest, HaltInsideAPhaseDoesNotEndItAsFailed) {
  auto m = load_ok(rules_.write("m.pl",
                                "mission :- execute_phase(1).\n"
                                "execute_phase(1) :- exec_start_timer(_), halt.\n"));
  ASSERT_TRUE(m);
  ScriptedHost host;
  PrologMissionQuery q(*m, host, 200000);
  EXPECT_EQ(prolog::Query::Status::Exception, run(q));
  EXPECT_TRUE(q.halted()) << q.exception_text();
  EXPECT_EQ((std::vector<std::string>{"phase 1", "call start_timer"}), host.events)
      << "the phase ends with the mission (the executor closes it as cancelled)";
}

TEST_F(PrologMissionTest, SystemHaltEndsTheMissionNotTheProcess) {
  auto m = load_ok(rules_.write("m.pl",
                                "mission :- exec_start_timer(_), system:halt(0), exec_submerge(_).\n"
                                "mission :- exec_surface(_).\n"));
  ASSERT_TRUE(m);
  ScriptedHost host;
  PrologMissionQuery q(*m, host, 200000);
  EXPECT_EQ(prolog::Query::Status::Exception, run(q));
  ASSERT_TRUE(q.halted()) << q.exception_text();
  EXPECT_EQ(std::vector<std::string>{"call start_timer"}, host.events) << "the next call ends it";
}

TEST_F(PrologMissionTest, DirectivesThatLoopOrHaltOrLoadNothingAreLoadErrors) {
  for (const auto& [text, expected] : std::vector<std::pair<std::string, std::string>>{
           {":- repeat, fail.\nmission.\n", "the load used up its inferences"},
           {":- halt.\nmission.\n", "the rules called halt while loading"},
           {":- system:halt(0).\nmission.\n", "the rules called halt while loading"},
           {":- consult(not_there).\nmission.\n", "not_there"}}) {
    Reported messages;
    LoadLimits limits;  // the loop meets its inference limit first, however loaded the machine
    limits.time = std::chrono::seconds(120);
    auto m = PrologMission::load(rules_.write("d.pl", text), tactical::Catalogue::builtin(), messages.sources,
                                 messages.sink, limits);
    ASSERT_FALSE(m.ok()) << text;
    std::string all = messages.text();
    EXPECT_NE(std::string::npos, all.find(expected)) << text << all;
    EXPECT_NE(std::string::npos, all.find("d.pl")) << "every message has a place: " << all;
    EXPECT_EQ(std::string::npos, all.find("Unknown message")) << all;
  }
  EXPECT_TRUE(prolog::call_once("true").value()) << "the process lives on";
}

TEST_F(PrologMissionTest, EndlessRecursionRunsOutOfStackOrInferences) {
  auto m = load_ok(rules_.write("m.pl", "mission :- deeper(0).\ndeeper(N) :- M is N + 1, deeper(M), true.\n"));
  ASSERT_TRUE(m);
  ScriptedHost host;
  PrologMissionQuery q(*m, host, 10'000'000);
  EXPECT_EQ(prolog::Query::Status::Exception, run(q));
  EXPECT_TRUE(q.out_of_stack() || q.inference_limit_exceeded()) << q.exception_text().substr(0, 200);
}

TEST_F(PrologMissionTest, HaltEndsTheRulesNotTheProcess) {
  auto m = load_ok(rules_.write("m.pl", "mission :- exec_start_timer(_), halt(2).\n"));
  ASSERT_TRUE(m);
  ScriptedHost host;
  PrologMissionQuery q(*m, host, 100000);
  EXPECT_EQ(prolog::Query::Status::Exception, run(q));
  ASSERT_TRUE(q.halted());
  EXPECT_EQ(2, *q.halted());
}

TEST_F(PrologMissionTest, CancellingAYieldedQueryLeavesPrologUsable) {
  auto m = load_ok(rules_.write("m.pl", "mission :- repeat, exec_sleep(1, _), fail.\n"));
  ASSERT_TRUE(m);
  {
    ScriptedHost host;
    PrologMissionQuery q(*m, host, 100000);
    EXPECT_EQ(prolog::Query::Status::Yield, q.next());
    EXPECT_EQ(prolog::Query::Status::Yield, q.next());
    q.close();  // while the rules wait for an answer
  }
  {
    ScriptedHost host;
    host.cancel = true;
    PrologMissionQuery q(*m, host, 100000);
    EXPECT_EQ(prolog::Query::Status::Yield, q.next());
    EXPECT_EQ(prolog::Query::Status::Exception, q.next());
    EXPECT_EQ("strata_cancelled", q.exception_text());
  }
  EXPECT_TRUE(prolog::call_once("true").value());
}

TEST_F(PrologMissionTest, EachLoadStartsFromAFreshDatabase) {
  std::string path = rules_.write("m.pl", R"(
:- dynamic count/1.
count(0).
mission :- retract(count(N)), M is N + 1, assertz(count(M)), exec_sleep(M, _).
)");
  for (int i = 0; i < 3; ++i) {
    auto m = load_ok(path);
    ASSERT_TRUE(m);
    ScriptedHost host;
    PrologMissionQuery q(*m, host, 100000);
    run(q);
    EXPECT_EQ(std::vector<std::string>{"call sleep 1"}, host.events) << "load " << i;
  }
}

TEST_F(PrologMissionTest, FilesLoadedByTheMissionComeFromItsFolder) {
  rules_.write("phase2.pl", "execute_phase(2) :- exec_submerge(_).\n");
  auto m = load_ok(rules_.write("m.pl",
                                ":- multifile execute_phase/1.\n:- consult(phase2).\n"
                                "mission :- execute_phase(2).\n"));
  ASSERT_TRUE(m);
  ScriptedHost host;
  PrologMissionQuery q(*m, host, 100000);
  run(q);
  EXPECT_EQ((std::vector<std::string>{"phase 2", "call submerge", "end 2 done"}), host.events);
}

TEST_F(PrologMissionTest, APredicateSplitAcrossFilesWithoutMultifileIsAnError) {
  rules_.write("phase2.pl", "execute_phase(2) :- exec_submerge(_).\n");
  Reported messages;
  auto m = PrologMission::load(rules_.write("m.pl", ":- consult(phase2).\nexecute_phase(1).\nmission.\n"),
                               tactical::Catalogue::builtin(), messages.sources, messages.sink);
  ASSERT_FALSE(m.ok()) << "the second file would silently wipe the first one's clauses";
  ASSERT_EQ(1u, messages.size());
  EXPECT_EQ(2u, messages.place(0).line);
  EXPECT_NE(std::string::npos, messages[0].message.find("declare `:- multifile execute_phase/1.`"))
      << messages[0].message;
  EXPECT_EQ(std::string::npos, messages[0].message.find("strata_mission_")) << "no internal module names";
}

TEST_F(PrologMissionTest, ABadArgumentRaisesInTheRules) {
  auto m = load_ok(rules_.write("m.pl", "mission :- exec_sleep(_, _).\n"));
  ASSERT_TRUE(m);
  ScriptedHost host;
  PrologMissionQuery q(*m, host, 100000);
  EXPECT_EQ(prolog::Query::Status::Exception, run(q));
  EXPECT_NE(std::string::npos, q.exception_text().find("instantiation_error")) << q.exception_text();
  EXPECT_TRUE(host.events.empty());
}

// Set while a test calls halt in rules many times: SWI-Prolog ending the
// process then (with status 0, which ctest would count as a pass) is a failure.
bool g_halting_in_rules = false;

TEST_F(PrologMissionTest, SystemHaltInEarlierRulesLeavesStopsUncatchableAndTheProcessAlive) {
  // Regression: system:halt/0,1 went through SWI-Prolog's halt, cancelled
  // in an at_halt hook. A cancelled halt left SWI's trace suspension one
  // off, and from then on it no longer called the exception hook for the
  // rules' queries: a catch-all swallowed the inference limit (and the
  // prolog::interrupt). And SWI ends the process anyway after ten cancelled halts.
  auto halting = [this](int i) {
    auto h = load_ok(rules_.write("h.pl",
                                  "mission :- exec_start_timer(_), catch(system:halt(0), _, true), "
                                  "exec_submerge(_).\n"));
    ASSERT_TRUE(h);
    ScriptedHost host;
    PrologMissionQuery q(*h, host, 100000);
    EXPECT_EQ(prolog::Query::Status::Exception, run(q)) << "halt " << i;
    ASSERT_TRUE(q.halted()) << "halt " << i << ": " << q.exception_text();
    EXPECT_EQ(std::vector<std::string>{"call start_timer"}, host.events) << "halt " << i;
  };
  halting(0);
  Reported messages;
  auto d = PrologMission::load(rules_.write("d.pl", ":- system:halt(0).\nmission.\n"), tactical::Catalogue::builtin(),
                               messages.sources, messages.sink);
  ASSERT_FALSE(d.ok());

  auto m = load_ok(rules_.write("m.pl",
                                "mission :- exec_start_timer(_), ( between(1, 3, _), catch(burn, _, true), "
                                "fail ; report(swallowed) ).\n"
                                "burn :- between(1, 1000000, _), fail ; true.\n"));
  ASSERT_TRUE(m);
  ScriptedHost host;
  PrologMissionQuery q(*m, host, 200000);
  EXPECT_EQ(prolog::Query::Status::Exception, run(q));
  EXPECT_TRUE(q.inference_limit_exceeded()) << q.exception_text();
  EXPECT_EQ(std::vector<std::string>{"call start_timer"}, host.events) << "the catch-all swallowed the limit";

  static bool guard_installed = false;
  if (!guard_installed) {
    guard_installed = true;
    std::atexit([] {
      if (g_halting_in_rules) {
        std::fputs("SWI-Prolog ended the process: the rules' halt reached it\n", stderr);
        std::_Exit(1);
      }
    });
  }
  g_halting_in_rules = true;
  for (int i = 1; i <= 11; ++i) halting(i);
  g_halting_in_rules = false;
}

}  // namespace
}  // namespace strata::strategic
