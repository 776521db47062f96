// The PROLOG executor against a scripted Tactical level: calls, outcomes,
// limits, phases, one mission at a time.
#include "strategic/prolog_executor_test_support.h"

namespace strata::strategic::prolog_testing {
namespace {

TEST_F(PrologExecutorTest, NominalRunCallsInOrderAndTellsObserversEverything) {
  auto m = rules("nominal", R"(
:- dynamic complete/1, abort/1.
mission :- exec_start_timer(T), T == 1,
           execute_phase(descend), !, execute_phase(check), !,
           ( execute_phase(extra) -> true ; true ), execute_phase(finish), !.
execute_phase(descend) :- exec_sleep(2, _), ask_depth_reached(1), report('deep enough'),
                          assertz(complete(descend)).
execute_phase(check) :- ask_system_problem(1), !, assertz(complete(check)).
execute_phase(check) :- report("problem free"), assertz(abort(check)).
execute_phase(extra) :- ask_time_out(1).
execute_phase(finish) :- execute_phase(surfacing), ood('shutdown_network', _).
execute_phase(surfacing) :- exec_surface(_).
)");
  ASSERT_TRUE(m);
  Session r(*m);
  r.start();
  EXPECT_TRUE(r.executor->running());
  EXPECT_EQ("start_timer", r.tactics.names());
  for (bool answer : {true, true, true}) r.tactics.answer(answer);  // start_timer, sleep, depth_reached
  // The REPORT went out and the rules went on without waiting for it.
  EXPECT_EQ("start_timer sleep(2) depth_reached report(deep enough) system_problem", r.tactics.names());
  EXPECT_EQ(2u, r.tactics.pending.size()) << "the report's reply and system_problem's";
  // system_problem 0: the other clause; time_out 0: phase extra fails.
  for (bool answer : {false, false, true, true}) r.tactics.answer(answer);
  EXPECT_EQ(
      "start_timer sleep(2) depth_reached report(deep enough) system_problem report(problem free) "
      "time_out surface shutdown_network",
      r.tactics.names());
  ASSERT_TRUE(r.result);
  EXPECT_EQ(Outcome::Completed, r.result->outcome) << r.result->reason;
  EXPECT_EQ("", r.result->exit);
  EXPECT_EQ("", r.result->reason);
  EXPECT_FALSE(r.result->call_error);
  EXPECT_NEAR(0.7, r.result->sim_time_s, 1e-9);
  EXPECT_FALSE(r.executor->running());
  EXPECT_EQ((Strings{"start nominal#0 parent 0 depth 0",
                     "action 1 exec start_timer in 0",
                     "finish 1 start_timer=1 in nominal#0",
                     "start descend#1 parent 0 depth 1",
                     "action 2 exec sleep in 1",
                     "finish 2 sleep=1 in descend#1",
                     "action 3 ask depth_reached in 1",
                     "finish 3 depth_reached=1 in descend#1",
                     "action 4 report report in 1",
                     "end descend#1 'complete' 0",
                     "start check#2 parent 0 depth 1",
                     "action 5 ask system_problem in 2",
                     "finish 5 system_problem=0 in check#2",
                     "action 6 report report in 2",
                     "end check#2 'abort' 1",
                     "start extra#3 parent 0 depth 1",
                     "action 7 ask time_out in 3",
                     "finish 7 time_out=0 in extra#3",
                     "end extra#3 'failed' 1",
                     "start finish#4 parent 0 depth 1",
                     "start surfacing#5 parent 4 depth 2",
                     "action 8 exec surface in 5",
                     "finish 8 surface=1 in surfacing#5",
                     "end surfacing#5 'done' 0",
                     "action 9 ood shutdown_network in 4",
                     "finish 9 shutdown_network=1 in finish#4",
                     "end finish#4 'done' 0",
                     "end nominal#0 '' 0",
                     "mission_ended completed",
                     "on_end"}),
            r.recorder.events);
  // The REPORTs' replies come after the end: nothing happens, not even a notice.
  r.tactics.answer_reports();
  EXPECT_TRUE(r.tactics.pending.empty());
  EXPECT_TRUE(r.recorder.notices.empty()) << r.recorder.notices[0];
  EXPECT_EQ(1, r.recorder.ended);
  EXPECT_EQ(1, r.on_end_calls);
  r.start();  // a finished executor does not start again
  EXPECT_EQ(9u, r.tactics.calls.size());
  EXPECT_EQ(1, r.on_end_calls);
}

TEST_F(PrologExecutorTest, CurrentPhaseMissionAbortEndsAborted) {
  auto r = run("aborting", R"(
:- dynamic current_phase/1.
current_phase(descend).
mission :- exec_start_timer(_), retract(current_phase(_)), assertz(current_phase(mission_abort)).
)",
               {true});
  ASSERT_TRUE(r && r->ended_with(Outcome::Aborted));
  EXPECT_EQ("mission_abort", r->result->exit);
  EXPECT_EQ("the rules ended with current_phase(mission_abort)", r->result->reason);
  EXPECT_EQ((Strings{"end aborting#0 'mission_abort' 1", "mission_ended aborted", "on_end"}), r->last(3));
}

TEST_F(PrologExecutorTest, HaltOrHaltNIsAnAbortAndNothingRunsAfterIt) {
  auto r = run("halt_two", "mission :- exec_start_timer(_), halt(2), exec_surface(_).\n", {true});
  ASSERT_TRUE(r && r->ended_with(Outcome::Aborted)) << (r ? r->why() : "");
  EXPECT_EQ("mission_abort", r->result->exit);
  EXPECT_EQ("the rules called halt(2)", r->result->reason);
  EXPECT_EQ("start_timer", r->tactics.names()) << "halt ends the rules: exec_surface is never called";

  auto r0 = run("halt_zero", "mission :- exec_start_timer(_), halt, exec_surface(_).\n", {true});
  ASSERT_TRUE(r0 && r0->ended_with(Outcome::Aborted)) << (r0 ? r0->why() : "");
  EXPECT_EQ("the rules called halt", r0->result->reason);
  EXPECT_EQ("mission_abort", r0->result->exit);
  EXPECT_EQ("start_timer", r0->tactics.names());
  EXPECT_EQ((Strings{"end halt_zero#0 'mission_abort' 1", "mission_ended aborted", "on_end"}), r0->last(3));

  auto r00 = run("halt_zero_code", "mission :- exec_start_timer(_), system:halt(0).\n", {true});
  ASSERT_TRUE(r00 && r00->ended_with(Outcome::Aborted)) << (r00 ? r00->why() : "");
  EXPECT_EQ("the rules called halt(0)", r00->result->reason);
}

TEST_F(PrologExecutorTest, HaltAtDepthEndsAbortedNotCompleted) {
  // Regression (issue 15): halt/0 after diving ended the run as completed
  // (exit 0), and the run's end path left the vehicle at depth.
  auto r = run("dive_and_halt", R"(
mission :- execute_phase(dive).
execute_phase(dive) :- exec_submerge(_), exec_sleep(5, _), ask_depth_reached(1), halt.
)",
               {true, true, true});
  ASSERT_TRUE(r && r->ended_with(Outcome::Aborted)) << (r ? r->why() : "");
  EXPECT_EQ("the rules called halt", r->result->reason);
  EXPECT_EQ("mission_abort", r->result->exit);
  EXPECT_FALSE(r->result->call_error);
  EXPECT_EQ("submerge sleep(5) depth_reached", r->tactics.names());
  EXPECT_EQ(
      (Strings{"end dive#1 cancelled", "end dive_and_halt#0 'mission_abort' 1", "mission_ended aborted", "on_end"}),
      r->last(4));
}

TEST_F(PrologExecutorTest, ExecOrOodAnsweredZeroFailsAsInCoral) {
  auto r = run("refused", "mission :- exec_submerge(X), ( X == 0 -> report(refused) ; true ).\n", {false});
  ASSERT_TRUE(r && r->ended_with(Outcome::Failed));
  EXPECT_NE(std::string::npos, r->result->reason.find("exec submerge was not executed")) << r->result->reason;
  EXPECT_FALSE(r->result->call_error);
  EXPECT_EQ("submerge", r->tactics.names()) << "the rules never saw the 0";
  EXPECT_EQ((Strings{"finish 1 submerge=0 in refused#0", "end refused#0 cancelled", "mission_ended failed", "on_end"}),
            r->last(4));

  auto o = run("ood_refused", "mission :- ood('start_network', _), exec_surface(_).\n", {false});
  ASSERT_TRUE(o && o->ended_with(Outcome::Failed));
  EXPECT_NE(std::string::npos, o->result->reason.find("ood start_network was not executed")) << o->result->reason;
  EXPECT_EQ("start_network", o->tactics.names());
}

TEST_F(PrologExecutorTest, AskAnsweredZeroIsAnAnswerNotAFailure) {
  // depth_reached 0: X == 0 holds; time_out 0: ask_time_out(1) fails and the else branch surfaces.
  auto r = run("asking", "mission :- ask_depth_reached(X), X == 0, ask_time_out(1) -> true ; exec_surface(_).\n",
               {false, false, true});
  ASSERT_TRUE(r);
  EXPECT_EQ("depth_reached time_out surface", r->tactics.names());
  ASSERT_TRUE(r->ended_with(Outcome::Completed)) << r->why();
}

TEST_F(PrologExecutorTest, FailedCallEndsTheMissionWithItsErrorCode) {
  auto r = run("timeout", "mission :- exec_sleep(1, _), exec_surface(_).\n", {});
  ASSERT_TRUE(r);
  r->tactics.fail_call({tactical::CallError::Kind::TimedOut, std::nullopt, "no reply within 6 s"});
  ASSERT_TRUE(r->ended_with(Outcome::Failed));
  EXPECT_EQ("exec sleep failed: no reply within 6 s", r->result->reason);
  EXPECT_EQ(tactical::CallError::Kind::TimedOut, r->result->call_error);
  EXPECT_EQ("sleep(1)", r->tactics.names());
  EXPECT_EQ((Strings{"end timeout#0 cancelled", "mission_ended failed", "on_end"}), r->last(3));
}

TEST_F(PrologExecutorTest, CancelWithACallInFlightEndsNowAndTheLateReplyIsANotice) {
  auto m = rules("cancelled", R"(
mission :- execute_phase(one).
execute_phase(one) :- exec_sleep(5, _), exec_surface(_).
)");
  ASSERT_TRUE(m);
  Session r(*m);
  r.executor->cancel("not started");  // not running: nothing happens
  EXPECT_FALSE(r.result);
  r.start();
  r.executor->cancel("interrupted by the operator");
  ASSERT_TRUE(r.ended_with(Outcome::Failed));
  EXPECT_EQ("interrupted by the operator", r.result->reason);
  EXPECT_FALSE(r.result->call_error);
  EXPECT_FALSE(r.executor->running());
  r.executor->cancel("again");
  r.tactics.answer(true);  // the sleep's reply, late
  ASSERT_EQ(1u, r.recorder.notices.size());
  EXPECT_EQ("a reply for call 1, which the mission no longer waits for, was ignored", r.recorder.notices[0]);
  EXPECT_EQ("sleep(5)", r.tactics.names()) << "the rules did not go on";
  EXPECT_EQ((Strings{"start cancelled#0 parent 0 depth 0", "start one#1 parent 0 depth 1", "action 1 exec sleep in 1",
                     "end one#1 cancelled", "end cancelled#0 cancelled", "mission_ended failed", "on_end"}),
            r.recorder.events);
  EXPECT_EQ("interrupted by the operator", r.result->reason) << "the second cancel changed nothing";
  r.executor.reset();
  EXPECT_EQ(1, r.on_end_calls);
}

TEST_F(PrologExecutorTest, DestroyedWithACallInFlightTheReplyDoesNothing) {
  const std::string path = write("dropped.pl", "mission :- exec_sleep(3, _), exec_surface(_).\n");
  auto m = load(path);
  ASSERT_TRUE(m);
  Session r(*m);
  r.start();
  ASSERT_EQ(1u, r.tactics.pending.size());
  r.executor.reset();
  r.tactics.answer(true);  // would be a use after free without the weak self token
  EXPECT_EQ("sleep(3)", r.tactics.names());
  EXPECT_EQ(0, r.recorder.ended);
  EXPECT_TRUE(r.recorder.notices.empty());
  EXPECT_FALSE(r.result);
  {
    // These rules have run: a second executor on them ends at once.
    Session rerun(*m);
    rerun.start();
    ASSERT_TRUE(rerun.ended_with(Outcome::Failed));
    EXPECT_EQ("these rules have run already: load the mission again for another run", rerun.result->reason);
    EXPECT_EQ("", rerun.tactics.names());
  }
  // The abandoned query left Prolog usable: the same file, loaded again
  // (once the first load is gone), runs.
  m.reset();
  auto reloaded = load(path);
  ASSERT_TRUE(reloaded);
  Session again(*reloaded);
  again.start();
  again.tactics.answer(true);
  again.tactics.answer(true);
  ASSERT_TRUE(again.ended_with(Outcome::Completed)) << again.why();
  EXPECT_EQ("sleep(3) surface", again.tactics.names());
}

TEST_F(PrologExecutorTest, MissionThatFailsIsFailed) {
  auto r = run("failing", "mission :- ask_depth_reached(1).\n", {false});
  ASSERT_TRUE(r && r->ended_with(Outcome::Failed));
  EXPECT_EQ("mission/0 failed: none of its rules succeeded", r->result->reason);
  EXPECT_EQ("", r->result->exit);
}

TEST_F(PrologExecutorTest, ExceptionEndsTheMissionWithItsText) {
  auto r = run("raising", "mission :- exec_start_timer(_), throw(sensor_gone(depth, 42)).\n", {true});
  ASSERT_TRUE(r && r->ended_with(Outcome::Failed));
  EXPECT_EQ("the rules raised an exception: sensor_gone(depth,42)", r->result->reason);
}

TEST_F(PrologExecutorTest, LoopWithoutPrimitiveCallsHitsTheInferenceLimit) {
  auto r = run("spinning", "mission :- exec_start_timer(_), spin(0).\nspin(N) :- N1 is N + 1, spin(N1).\n", {true},
               PrologOptions{100000});
  ASSERT_TRUE(r && r->ended_with(Outcome::Failed));
  EXPECT_EQ(
      "the rules made 100000 inferences without calling a primitive: an endless loop? "
      "(the limit is --inference-limit)",
      r->result->reason);
}

TEST_F(PrologExecutorTest, InferenceLimitCountsFromTheLastPrimitiveCall) {
  // Each burn is about 50,000 inferences: three of them exceed 100,000 in
  // all but never between two calls.
  auto r = run("busy", R"(
burn :- numlist(1, 12000, L), sum_list(L, _), msort(L, _), length(L, _), last(L, _).
mission :- burn, exec_sleep(1, _), burn, exec_sleep(1, _), burn.
)",
               {true, true}, PrologOptions{100000});
  ASSERT_TRUE(r && r->ended_with(Outcome::Completed)) << (r ? r->why() : "");
  // And past the limit in one stretch, the same burns fail.
  auto again = load(write("busy_again.pl", read_file(missions_.back()->path())));
  ASSERT_TRUE(again);
  Session tight(*again, PrologOptions{20000});
  tight.start();
  ASSERT_TRUE(tight.ended_with(Outcome::Failed));
  EXPECT_NE(std::string::npos, tight.result->reason.find("20000 inferences")) << tight.result->reason;
  EXPECT_EQ("", tight.tactics.names());
}

TEST_F(PrologExecutorTest, OpenPhasesEndCancelledInnermostFirstBeforeTheMission) {
  // submerge refused: the mission fails inside three phases.
  auto r = run("nested", R"(
mission :- execute_phase(outer).
execute_phase(outer) :- exec_start_timer(_), execute_phase(middle).
execute_phase(middle) :- execute_phase(inner).
execute_phase(inner) :- exec_submerge(_).
)",
               {true, false});
  ASSERT_TRUE(r && r->ended_with(Outcome::Failed));
  EXPECT_EQ((Strings{"start nested#0 parent 0 depth 0", "start outer#1 parent 0 depth 1",
                     "action 1 exec start_timer in 1", "finish 1 start_timer=1 in outer#1",
                     "start middle#2 parent 1 depth 2", "start inner#3 parent 2 depth 3", "action 2 exec submerge in 3",
                     "finish 2 submerge=0 in inner#3", "end inner#3 cancelled", "end middle#2 cancelled",
                     "end outer#1 cancelled", "end nested#0 cancelled", "mission_ended failed", "on_end"}),
            r->recorder.events);
}

TEST_F(PrologExecutorTest, OneMissionAtATimePerProcess) {
  auto first = load(write("first.pl", "mission :- exec_sleep(1, _).\n"));
  auto second = load(write("second.pl", "mission :- exec_sleep(2, _).\n"));
  ASSERT_TRUE(first && second);
  Session a(*first);
  a.start();
  ASSERT_EQ(1u, a.tactics.pending.size()) << "a waits for the vehicle";
  Session b(*second);
  b.start();
  ASSERT_TRUE(b.ended_with(Outcome::Failed));
  EXPECT_EQ("another PROLOG mission is running in this process: one at a time", b.result->reason);
  a.tactics.answer(true);
  ASSERT_TRUE(a.ended_with(Outcome::Completed)) << a.why();
  // Once a has ended, the engine is free again.
  auto third = load(write("third.pl", "mission :- exec_sleep(3, _).\n"));
  ASSERT_TRUE(third);
  Session c(*third);
  c.start();
  c.tactics.answer(true);
  EXPECT_TRUE(c.ended_with(Outcome::Completed)) << c.why();
}

TEST_F(PrologExecutorTest, EachRunStartsFromAFreshDatabase) {
  const std::string path = write("counting.pl", R"(
:- dynamic runs/1.
runs(0).
mission :- retract(runs(N)), N1 is N + 1, assertz(runs(N1)), exec_sleep(N1, _).
)");
  for (int run = 0; run < 2; ++run) {
    auto m = load(path);
    ASSERT_TRUE(m);
    Session r(*m);
    r.start();
    r.tactics.answer(true);
    ASSERT_TRUE(r.ended_with(Outcome::Completed)) << "run " << run;
    EXPECT_EQ("sleep(1)", r.tactics.names()) << "run " << run << " saw the previous run's runs/1";
  }
}

}  // namespace
}  // namespace strata::strategic::prolog_testing
