#include "strategic/coral_engine.h"

#include <deque>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include <gtest/gtest.h>

#include "coral/test_support.h"
#include "strategic/fake_tactics.h"
#include "strategic/log_observer.h"
#include "tactical/catalogue.h"
#include "tactical/tactical_level.h"
#include "tactical/test_rig.h"

namespace strata::strategic {
namespace {

using coral::testing::compile_text;

// Answers the oldest unanswered call (or the i-th call).
struct FakeTactics final : testing::FakeTacticsBase {
  void answer(bool value) {
    ASSERT_FALSE(pending.empty());
    reply(pending.front(), tactical::CallOutcome{value, time_s});
  }
  void answer_call(std::size_t i, bool value) { reply(i, tactical::CallOutcome{value, time_s}); }
  void fail_oldest(tactical::CallError error) { take(pending.front())(std::move(error)); }
  void reply(std::size_t i, tactical::CallOutcome outcome) {
    auto h = take(i);
    time_s += 0.1;
    h(outcome);
  }
};

// Records what observers are told, as short strings.
struct Recorder final : Observer {
  void phase_started(const PhaseStart& e) override {
    events.push_back(fmt::format("start {} depth {}", e.name, e.depth));
  }
  void phase_ended(const PhaseEnd& e) override {
    events.push_back(fmt::format("end {} {}", e.name, e.cancelled ? "cancelled" : std::string(e.exit)));
  }
  void fired(const Firing& e) override { fired_names.push_back(std::string(e.transition_name)); }
  void notice(const Notice& e) override { notices.push_back(e.text); }
  void mission_ended(const MissionResult& r) override {
    ++ended;
    result = r;
  }

  std::vector<std::string> events;
  std::vector<std::string> fired_names;
  std::vector<std::string> notices;
  int ended = 0;
  MissionResult result;
};

struct Harness {
  explicit Harness(const std::string& text, EngineOptions options = {},
                   std::vector<std::pair<std::string, std::string>> extra = {})
      : compiled(compile_text(text, extra)) {
    EXPECT_TRUE(compiled->program.has_value()) << ::testing::PrintToString(compiled->kinds());
    if (!compiled->program) return;
    engine = std::make_unique<CoralEngine>(*compiled->program, tactics, options);
    engine->add_observer(recorder);
  }
  void start() {
    ASSERT_TRUE(engine);
    engine->start([this](const MissionResult& r) { on_end_result = r; });
  }

  std::unique_ptr<coral::testing::Compiled> compiled;
  FakeTactics tactics;
  Recorder recorder;
  std::unique_ptr<CoralEngine> engine;
  std::optional<MissionResult> on_end_result;
};

TEST(CoralEngine, ConflictGoesToTheFirstDeclaredTransition) {
  Harness h(R"(mission m {
    place a = 1; exit x, y;
    transition first  { wait { a } action { TACTIC(EXEC, f1, x) } }
    transition second { wait { a } action { TACTIC(EXEC, f2, y) } }
  })");
  h.start();
  EXPECT_EQ("f1", h.tactics.names());
  h.tactics.answer(true);
  ASSERT_TRUE(h.on_end_result);
  EXPECT_EQ(Outcome::Completed, h.on_end_result->outcome);
  EXPECT_EQ("x", h.on_end_result->exit);
}

TEST(CoralEngine, PriorityBeatsDeclarationOrder) {
  Harness h(R"(mission m {
    place a = 1; exit x, y;
    transition first  { wait { a } action { TACTIC(EXEC, f1, x) } }
    transition second priority 5 { wait { a } action { TACTIC(EXEC, f2, y) } }
  })");
  h.start();
  EXPECT_EQ("f2", h.tactics.names());
  h.tactics.answer(true);
  ASSERT_TRUE(h.on_end_result);
  EXPECT_EQ(Outcome::Aborted, h.on_end_result->outcome) << "a later exit is an abort";
  EXPECT_EQ("y", h.on_end_result->exit);
}

TEST(CoralEngine, SeededChoiceIsReproducibleAndReachesEveryCandidate) {
  const std::string text = R"(mission m {
    place a = 1; exit x, y, z;
    transition one   { wait { a } action { TACTIC(EXEC, f1, x) } }
    transition two   { wait { a } action { TACTIC(EXEC, f2, y) } }
    transition three { wait { a } action { TACTIC(EXEC, f3, z) } }
    transition low priority -1 { wait { a } action { TACTIC(EXEC, never, z) } }
  })";
  std::set<std::string> seen;
  for (std::uint64_t seed = 0; seed < 40; ++seed) {
    Harness a(text, EngineOptions{seed});
    Harness b(text, EngineOptions{seed});
    a.start();
    b.start();
    EXPECT_EQ(a.tactics.names(), b.tactics.names()) << "seed " << seed;
    seen.insert(a.tactics.names());
  }
  EXPECT_EQ((std::set<std::string>{"f1", "f2", "f3"}), seen) << "a lower priority is never chosen";
}

TEST(CoralEngine, ArcWeightsTakeAndGiveThatManyTokens) {
  Harness h(R"(mission m {
    place a = 5; place b, c; exit done;
    transition t { wait { a*2 } signal { b*3 } }
    transition u { wait { b*4 } signal { c } }
    transition v { wait { c, a } action { TACTIC(EXEC, f, done) } }
  })");
  h.start();
  // t fires twice (a 5 -> 1, b 6), u once (b 2, c 1), then v takes c and a.
  EXPECT_EQ((std::vector<std::string>{"t", "t", "u", "v"}), h.recorder.fired_names);
  EXPECT_EQ("m: b:2", h.engine->marking_text());
  h.tactics.answer(true);
  EXPECT_EQ(Outcome::Completed, h.on_end_result->outcome);
}

TEST(CoralEngine, TwoActionsInFlightAtOnceEachWithItsOwnReply) {
  Harness h(R"(mission m {
    place s = 1; place l, r, l_done, r_done; exit done;
    transition fork  { wait { s } signal { l, r } }
    transition left  { wait { l } action { TACTIC(EXEC, slow, l_done) } }
    transition right { wait { r } action { TACTIC(ASK, quick, r_done, r) } }
    transition join  { wait { l_done, r_done } signal { done } }
  })");
  h.start();
  EXPECT_EQ("slow quick", h.tactics.names());
  EXPECT_EQ(2u, h.engine->in_flight());
  h.tactics.answer_call(1, false);  // quick answers first: 0 -> back to r, asks again
  EXPECT_EQ("slow quick quick", h.tactics.names());
  EXPECT_EQ(2u, h.engine->in_flight());
  h.tactics.answer_call(2, true);
  EXPECT_EQ("m: r_done:1", h.engine->marking_text());
  EXPECT_FALSE(h.on_end_result);
  h.tactics.answer_call(0, true);
  ASSERT_TRUE(h.on_end_result);
  EXPECT_EQ(Outcome::Completed, h.on_end_result->outcome);
}

TEST(CoralEngine, NestedPhasesStartAndEndInOrderAndMarkTheirCallers) {
  Harness h(R"(
    net inner { place s = 1; exit ok, bad;
      transition work { wait { s } action { TACTIC(ASK, fine, ok, bad) } } }
    net outer { place s = 1; place inner_ok, inner_bad; exit ok, bad;
      transition go   { wait { s } action { PHASE(inner, inner_ok, inner_bad) } }
      transition pass { wait { inner_ok } action { TACTIC(REPORT, "inner done") } signal { ok } }
      transition fail { wait { inner_bad } signal { bad } } }
    mission m { place s = 1; place after; exit done, aborted;
      transition run    { wait { s } action { PHASE(outer, after, aborted) } }
      transition finish { wait { after } signal { done } } }
  )");
  h.start();
  EXPECT_EQ("fine", h.tactics.names());
  EXPECT_EQ(3u, h.engine->live_instances().size());
  h.tactics.answer(true);
  ASSERT_TRUE(h.on_end_result);
  EXPECT_EQ(Outcome::Completed, h.on_end_result->outcome);
  EXPECT_EQ("fine report(inner done)", h.tactics.names()) << "a REPORT beside an exit signal is still sent";
  EXPECT_EQ((std::vector<std::string>{"start m depth 0", "start outer depth 1", "start inner depth 2", "end inner ok",
                                      "end outer ok", "end m done"}),
            h.recorder.events);
  // A REPORT is not waited for: its reply, after the mission ended, is not
  // even a notice.
  h.tactics.answer(true);
  EXPECT_TRUE(h.recorder.notices.empty());
  EXPECT_EQ(1, h.recorder.ended);
}

// Issue 20: a phase net with parameters runs with the values of the PHASE
// call that started it; the calls it issues carry those numbers, through a
// nested PHASE too, and two instances of one net running at once keep their
// own values.
TEST(CoralEngine, PhaseArgumentsAreSubstitutedIntoTheCallsTheInstanceIssues) {
  Harness h(R"(
    net leg(x0, y0, string label) { place s = 1, said; exit done;
      transition say { wait { s } action { TACTIC(OOD, note(label), said) } }
      transition go  { wait { said } action { TACTIC(EXEC, track(x0, y0, 100, y0), done) } } }
    net there_and_back(y) { place s = 1, out; exit done;
      transition one { wait { s } action { PHASE(leg(0, y, "out"), out) } }
      transition two { wait { out } action { PHASE(leg(100, -5.5, "back"), done) } } }
    mission m { place s = 1, a, b; exit completed;
      transition both { wait { s } action { PHASE(there_and_back(20), a), PHASE(leg(7, 8, "side"), b) } }
      transition end  { wait { a, b } signal { completed } } }
  )");
  h.start();
  // leg(7, 8) is started by the mission itself, leg(0, 20) a phase deeper:
  // the first calls of the side leg come first.
  EXPECT_EQ("note(side) note(out)", h.tactics.names());
  h.tactics.answer(true);  // note(side)
  h.tactics.answer(true);  // note(out)
  EXPECT_EQ("note(side) note(out) track(7,8,100,8) track(0,20,100,20)", h.tactics.names());
  h.tactics.answer(true);
  h.tactics.answer(true);
  h.tactics.answer(true);  // note(back)
  h.tactics.answer(true);
  EXPECT_EQ("note(side) note(out) track(7,8,100,8) track(0,20,100,20) note(back) track(100,-5.5,100,-5.5)",
            h.tactics.names());
  ASSERT_TRUE(h.on_end_result);
  EXPECT_EQ(Outcome::Completed, h.on_end_result->outcome);
}

// A REPORT may name a string parameter of its net: it reports the value of
// the call that started the instance, a literal or the caller's own
// parameter passed on.
TEST(CoralEngine, ReportOfAParameterSendsTheCallsValue) {
  Harness h(R"(
    net say(string text) { place s = 1; exit done;
      transition t { wait { s } action { TACTIC(REPORT, text) } signal { done } } }
    net relay(string what) { place s = 1; exit done;
      transition t { wait { s } action { PHASE(say(what), done) } } }
    mission m { place s = 1, a; exit completed;
      transition one { wait { s } action { PHASE(say("leg 1 done"), a) } }
      transition two { wait { a } action { PHASE(relay("passed on"), completed) } } }
  )");
  h.start();
  EXPECT_EQ("report(leg 1 done) report(passed on)", h.tactics.names());
  ASSERT_TRUE(h.on_end_result);
  EXPECT_EQ(Outcome::Completed, h.on_end_result->outcome);
}

TEST(CoralEngine, ReplyForAnUnknownIdIsNoticedAndIgnored) {
  Harness h(R"(mission m { place s = 1; exit done;
    transition t { wait { s } action { TACTIC(EXEC, f, done) } } })");
  h.start();
  h.engine->deliver(999, tactical::CallOutcome{true, 0.0});
  ASSERT_EQ(1u, h.recorder.notices.size());
  EXPECT_EQ("reply for unknown action 999, ignored", h.recorder.notices[0]);
  EXPECT_FALSE(h.on_end_result);
  EXPECT_EQ("m: (empty)", h.engine->marking_text());
  h.tactics.answer(true);
  ASSERT_TRUE(h.on_end_result);
  EXPECT_EQ(Outcome::Completed, h.on_end_result->outcome);
}

TEST(CoralEngine, ReplyForAPhaseThatEndedIsIgnored) {
  Harness h(R"(
    net p { place s = 1; place a, b; exit done;
      transition fork { wait { s } signal { a, b } }
      transition slow { wait { a } action { TACTIC(EXEC, slow, done) } }
      transition fast { wait { b } action { TACTIC(EXEC, fast, done) } } }
    mission m { place s = 1; place after; exit finished;
      transition run { wait { s } action { PHASE(p, after) } }
      transition end { wait { after } action { TACTIC(EXEC, last, finished) } } }
  )");
  h.start();
  EXPECT_EQ("slow fast", h.tactics.names());
  h.tactics.answer_call(1, true);  // fast marks the exit: the phase ends
  EXPECT_EQ("slow fast last", h.tactics.names());
  h.tactics.answer_call(0, true);  // slow's reply is late
  ASSERT_EQ(1u, h.recorder.notices.size());
  EXPECT_NE(std::string::npos, h.recorder.notices[0].find("phase that has ended"));
  EXPECT_FALSE(h.on_end_result);
  h.tactics.answer(true);
  EXPECT_EQ(Outcome::Completed, h.on_end_result->outcome);
}

TEST(CoralEngine, FailedCallEndsTheMissionWithTheReason) {
  Harness h(R"(mission m { place s = 1; exit done;
    transition t { wait { s } action { TACTIC(ASK, depth_reached, done, s) } } })");
  h.start();
  h.tactics.fail_oldest({tactical::CallError::Kind::LinkLost, std::nullopt, "link lost"});
  ASSERT_TRUE(h.on_end_result);
  EXPECT_EQ(Outcome::Failed, h.on_end_result->outcome);
  EXPECT_EQ("ask depth_reached failed: link lost", h.on_end_result->reason);
  EXPECT_EQ(tactical::CallError::Kind::LinkLost, h.on_end_result->call_error);
  EXPECT_EQ(1, h.recorder.ended);
}

TEST(CoralEngine, ExecAnsweredZeroIsAFailure) {
  Harness h(R"(mission m { place s = 1; exit done;
    transition t { wait { s } action { TACTIC(EXEC, submerge, done) } } })");
  h.start();
  h.tactics.answer(false);
  ASSERT_TRUE(h.on_end_result);
  EXPECT_EQ(Outcome::Failed, h.on_end_result->outcome);
  EXPECT_NE(std::string::npos, h.on_end_result->reason.find("exec submerge was not executed"));
}

TEST(CoralEngine, StallIsReportedWithTheMarking) {
  Harness h(R"(mission m { place s = 1; place a, b; exit done;
    transition t { wait { s } signal { a } }
    transition u { wait { a, b } signal { done } } })");
  h.start();
  ASSERT_TRUE(h.on_end_result);
  EXPECT_EQ(Outcome::Failed, h.on_end_result->outcome);
  EXPECT_EQ("mission stalled: no transition enabled and no action in flight; marking: m: a:1", h.on_end_result->reason);
  EXPECT_TRUE(h.on_end_result->stalled) << "typed: the campaign's no_stall reads this, not the words";
}

TEST(CoralEngine, MissionWithoutExitsCompletesWhenAtRest) {
  Harness h(R"(mission m { place s = 1; place a;
    transition t { wait { s } action { TACTIC(EXEC, f, a) } } })");
  h.start();
  EXPECT_FALSE(h.on_end_result);
  h.tactics.answer(true);
  ASSERT_TRUE(h.on_end_result);
  EXPECT_EQ(Outcome::Completed, h.on_end_result->outcome);
}

TEST(CoralEngine, NetThatCyclesWithoutActingIsStopped) {
  EngineOptions options;
  options.max_firings_per_event = 1000;
  Harness h(R"(mission m { place a = 1; place b; exit done;
    transition ab { wait { a } signal { b } }
    transition ba { wait { b } signal { a } } })",
            options);
  h.start();
  ASSERT_TRUE(h.on_end_result);
  EXPECT_EQ(Outcome::Failed, h.on_end_result->outcome);
  EXPECT_NE(std::string::npos, h.on_end_result->reason.find("cycles without acting"));
  EXPECT_EQ(1000u, h.engine->firings());
}

TEST(CoralEngine, CancelEndsTheRunAndLaterRepliesAreIgnored) {
  Harness h(R"(mission m { place s = 1; exit done;
    transition t { wait { s } action { TACTIC(EXEC, f, done) } } })");
  h.start();
  h.engine->cancel("interrupted by the operator");
  ASSERT_TRUE(h.on_end_result);
  EXPECT_EQ("interrupted by the operator", h.on_end_result->reason);
  EXPECT_FALSE(h.engine->running());
  h.tactics.answer(true);
  EXPECT_EQ(1, h.recorder.ended);
}

TEST(CoralEngine, LogObserverWritesFiringsMarksAndPhases) {
  Harness h(R"(
    net p { place s = 1; exit ok;
      transition go { wait { s } action { TACTIC(ASK, q, ok, s) } } }
    mission m { place s = 1; place after; exit done;
      transition run { wait { s } action { PHASE(p, after) } }
      transition fin { wait { after } signal { done } } }
  )");
  std::ostringstream out;
  auto log = tactical::MissionLog::to_stream(out, tactical::RunInfo{});
  ASSERT_TRUE(log.ok());
  LogObserver observer(log.value());
  h.engine->add_observer(observer);
  h.start();
  h.tactics.answer(true);
  std::string text = tactical::strip_wall_fields_from_log(out.str());
  std::string body = text.substr(text.find('\n') + 1);
  EXPECT_EQ(
      R"({"event":"phase_start","instance":0,"net":"m","parent":0,"caller":"","depth":0,"marking":{"s":1},"sim_time":0.0}
{"event":"fire","n":1,"instance":0,"net":"m","transition":"run","consumed":{"s":1},"produced":{},"sim_time":0.0}
{"event":"phase_start","instance":1,"net":"p","parent":0,"caller":"run","depth":1,"marking":{"s":1},"sim_time":0.0}
{"event":"fire","n":2,"instance":1,"net":"p","transition":"go","consumed":{"s":1},"produced":{},"sim_time":0.0}
{"event":"mark","instance":1,"net":"p","place":"ok","by":"q","sim_time":0.0}
{"event":"phase_end","instance":1,"net":"p","exit":"ok","result":"completed","sim_time":0.1}
{"event":"mark","instance":0,"net":"m","place":"after","by":"p","sim_time":0.1}
{"event":"fire","n":3,"instance":0,"net":"m","transition":"fin","consumed":{"after":1},"produced":{"done":1},"sim_time":0.1}
{"event":"phase_end","instance":0,"net":"m","exit":"done","result":"completed","sim_time":0.1}
)",
      body);
}

// Against the real vehicle: a phase that polls an ASK until the answer
// changes. Each question costs the vehicle one 0.1 s cycle, so simulated time
// moves with every call and the loop makes exactly one call per turn.
TEST(CoralEngine, AskPollingLoopAdvancesSimTimeOneCallPerTurn) {
  auto compiled = compile_text(R"(
    net watch { place s = 1; place polling; exit problem;
      transition poll { wait { s } action { TACTIC(ASK, system_problem, problem, s) } } }
    mission m { place s = 1; place up, seen; exit done;
      transition net_up { wait { s } action { TACTIC(OOD, start_network, up) } }
      transition go     { wait { up } action { PHASE(watch, seen) } }
      transition down   { wait { seen } action { TACTIC(OOD, shutdown_network, done) } } }
  )");
  ASSERT_TRUE(compiled->program);
  vehicle::Scenario scenario = vehicle::Scenario::nominal();
  scenario.faults.push_back(vehicle::Fault{vehicle::FaultKind::Leak, 5.0, 1.0, std::nullopt});
  tactical::testing::Rig rig(scenario);
  auto link = rig.connect();
  tactical::Catalogue catalogue = tactical::Catalogue::builtin();
  tactical::TacticalLevel level(rig.io, catalogue, link, nullptr, nullptr);
  std::uint64_t asks = 0;
  level.on_call([&](const tactical::CallRecord& r) { asks += r.primitive == "system_problem"; });
  TacticalTactics tactics(level);
  CoralEngine engine(*compiled->program, tactics);
  std::optional<MissionResult> result;
  engine.start([&](const MissionResult& r) { result = r; });
  ASSERT_TRUE(tactical::testing::run_until(rig.io, [&] { return result.has_value(); }));
  EXPECT_EQ(Outcome::Completed, result->outcome) << result->reason;
  EXPECT_GE(result->sim_time_s, 5.0);
  EXPECT_LT(result->sim_time_s, 5.5);
  // start_network takes the first cycle; then one ask per 0.1 s until 5.0 s.
  EXPECT_GE(asks, 48u);
  EXPECT_LE(asks, 51u);
  EXPECT_EQ(asks + 2, level.calls());
}

}  // namespace
}  // namespace strata::strategic
