// Guards in the CORAL Engine (docs/language.md, "guard"): pre-emption at
// every point of a run, which guard wins, polls that are not progress.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include "coral/test_support.h"
#include "strategic/coral_engine.h"
#include "strategic/fake_tactics.h"

namespace strata::strategic {
namespace {

using coral::testing::compile_text;

// Answers calls by index; each answer moves the clock by 0.1 s.
struct GuardTactics final : testing::FakeTacticsBase {
  void answer(std::size_t i, bool value) {
    auto h = take(i);
    time_s += 0.1;
    h(tactical::CallOutcome{value, time_s});
  }
  // The index of the pending call to `name` (the oldest one).
  std::size_t pending_call(std::string_view name) const {
    for (std::size_t i : pending) {
      if (calls[i].name == name) return i;
    }
    ADD_FAILURE() << "no pending call to " << name << " in: " << names();
    return 0;
  }
  bool has_pending(std::string_view name) const {
    return std::any_of(pending.begin(), pending.end(), [&](std::size_t i) { return calls[i].name == name; });
  }
};

struct GuardRecorder final : Observer {
  void phase_ended(const PhaseEnd& e) override {
    events.push_back(fmt::format("end {} {}", e.name, e.cancelled ? "cancelled" : std::string(e.exit)));
  }
  void action_started(const ActionStart& e) override {
    if (!e.guard.empty()) polls.push_back(fmt::format("{} {}", e.guard, e.primitive));
  }
  void guard_tripped(const GuardTrip& e) override {
    std::string phases, calls;
    for (const auto& p : e.preempted_phases) phases += (phases.empty() ? "" : ",") + p;
    for (const auto& c : e.preempted_calls) calls += (calls.empty() ? "" : ",") + c;
    events.push_back(fmt::format("trip {} in {} by {} [{}] [{}]", e.guard, e.net, e.condition, phases, calls));
  }
  std::vector<std::string> events;
  std::vector<std::string> polls;
};

struct GuardRun {
  explicit GuardRun(const std::string& text) : compiled(compile_text(text)) {
    EXPECT_TRUE(compiled->program.has_value()) << ::testing::PrintToString(compiled->kinds());
    if (!compiled->program) return;
    engine = std::make_unique<CoralEngine>(*compiled->program, tactics);
    engine->add_observer(recorder);
    engine->start([this](const MissionResult& r) { result = r; });
  }
  // Answers the pending guard sleep, then its ask with `value`.
  void poll(bool value, std::string_view ask = "system_problem") {
    tactics.answer(tactics.pending_call("sleep"), true);
    tactics.answer(tactics.pending_call(ask), value);
  }
  std::unique_ptr<coral::testing::Compiled> compiled;
  GuardTactics tactics;
  GuardRecorder recorder;
  std::unique_ptr<CoralEngine> engine;
  std::optional<MissionResult> result;
};

constexpr const char* kLongExec = R"(
  net up { place s = 1; exit done;
    transition rise { wait { s } action { TACTIC(EXEC, surface, done) } } }
  mission m {
    place begin = 1, waited, surfaced;
    exit completed, aborted;
    guard leak every 1 {
      when   { system_problem }
      action { TACTIC(REPORT, "leak"), PHASE(up, surfaced) }
    }
    transition hold  { wait { begin } action { TACTIC(EXEC, long_task, waited) } }
    transition done  { wait { waited } signal { completed } }
    transition close { wait { surfaced } signal { aborted } }
  })";

TEST(CoralGuards, FirstSleepGoesOutAfterTheNetsOwnFirstCalls) {
  GuardRun run(kLongExec);
  EXPECT_EQ("long_task sleep(1)", run.tactics.names());
  EXPECT_EQ((std::vector<std::string>{"leak sleep"}), run.recorder.polls);
}

TEST(CoralGuards, TripDuringALongExecForgetsItAndRunsTheHandler) {
  GuardRun run(kLongExec);
  run.poll(false);
  run.poll(false);
  EXPECT_FALSE(run.result);
  EXPECT_EQ("long_task sleep(1) system_problem sleep(1) system_problem sleep(1)", run.tactics.names())
      << "polled again at once after each answer 0";
  run.poll(true);
  EXPECT_EQ((std::vector<std::string>{"trip leak in m by system_problem [] [exec long_task]"}), run.recorder.events);
  EXPECT_TRUE(run.tactics.has_pending("surface")) << run.tactics.names();
  // The long exec answers after the trip: ignored, the handler goes on.
  run.tactics.answer(run.tactics.pending_call("long_task"), true);
  EXPECT_FALSE(run.result);
  run.tactics.answer(run.tactics.pending_call("surface"), true);
  ASSERT_TRUE(run.result);
  EXPECT_EQ(Outcome::Aborted, run.result->outcome);
  EXPECT_EQ("aborted", run.result->exit);
  EXPECT_FALSE(run.tactics.has_pending("sleep")) << "the guard stopped with the trip";
}

TEST(CoralGuards, TripEndsNestedPhasesOutermostFirst) {
  GuardRun run(R"(
    net inner { place s = 1, t; exit ok;
      transition wait_here { wait { s } action { TACTIC(EXEC, sleep(600), t) } }
      transition go_on { wait { t } signal { ok } } }
    net outer { place s = 1; exit ok;
      transition go { wait { s } action { PHASE(inner, ok) } } }
    net up { place s = 1; exit done;
      transition rise { wait { s } action { TACTIC(EXEC, surface, done) } } }
    mission m { place begin = 1, after, surfaced; exit completed, aborted;
      guard leak every 2 { when { altitude_low, system_problem } action { PHASE(up, surfaced) } }
      transition run { wait { begin } action { PHASE(outer, after) } }
      transition finish { wait { after } signal { completed } }
      transition close { wait { surfaced } signal { aborted } } }
  )");
  EXPECT_EQ("sleep(600) sleep(2)", run.tactics.names());
  run.tactics.answer(1, true);                                           // the guard's sleep
  run.tactics.answer(run.tactics.pending_call("altitude_low"), false);   // the first term: no
  run.tactics.answer(run.tactics.pending_call("system_problem"), true);  // the second: trips
  EXPECT_EQ((std::vector<std::string>{"trip leak in m by system_problem [outer (instance 1),inner (instance 2)] "
                                      "[exec sleep]",
                                      "end inner cancelled", "end outer cancelled"}),
            run.recorder.events);
  run.tactics.answer(0, true);  // the phase's sleep(600), late: ignored
  run.tactics.answer(run.tactics.pending_call("surface"), true);
  ASSERT_TRUE(run.result);
  EXPECT_EQ("aborted", run.result->exit);
}

TEST(CoralGuards, NotTermTripsOnAnswerZero) {
  GuardRun run(R"(mission m { place begin = 1, w; exit completed, lost;
      guard fix every 5 { when { not gps_available } signal { lost } }
      transition hold { wait { begin } action { TACTIC(EXEC, long_task, w) } }
      transition done { wait { w } signal { completed } } })");
  run.poll(true, "gps_available");
  EXPECT_FALSE(run.result);
  run.poll(false, "gps_available");
  ASSERT_TRUE(run.result);
  EXPECT_EQ("lost", run.result->exit);
}

// Inner: a phase's guard trips and its handler runs; the mission's guard
// trips while that handler runs, and pre-empts it: the outer guard wins.
TEST(CoralGuards, OuterGuardPreemptsAnInnerGuardsHandler) {
  GuardRun run(R"(
    net slow_stop { place s = 1; exit done;
      transition stop { wait { s } action { TACTIC(EXEC, stop_slowly, done) } } }
    net leg { place s = 1, t; exit ok, abort;
      guard floor every 1 { when { altitude_low } action { PHASE(slow_stop, abort) } }
      transition go { wait { s } action { TACTIC(EXEC, track, t) } }
      transition arrive { wait { t } signal { ok } } }
    net up { place s = 1; exit done;
      transition rise { wait { s } action { TACTIC(EXEC, surface, done) } } }
    mission m { place begin = 1, after, gave_up, surfaced; exit completed, aborted;
      guard leak every 1 { when { system_problem } action { PHASE(up, surfaced) } }
      transition run { wait { begin } action { PHASE(leg, after, gave_up) } }
      transition finish { wait { after } signal { completed } }
      transition back { wait { gave_up } action { PHASE(up, surfaced) } }
      transition close { wait { surfaced } signal { aborted } } }
  )");
  // track, then the mission's sleep, then the leg's (instances in the order started).
  EXPECT_EQ("track sleep(1) sleep(1)", run.tactics.names());
  run.tactics.answer(2, true);  // the leg's sleep
  run.tactics.answer(run.tactics.pending_call("altitude_low"), true);
  EXPECT_TRUE(run.tactics.has_pending("stop_slowly"));
  run.tactics.answer(1, true);  // the mission's sleep
  run.tactics.answer(run.tactics.pending_call("system_problem"), true);
  EXPECT_EQ((std::vector<std::string>{
                "trip floor in leg by altitude_low [] [exec track]",
                "trip leak in m by system_problem [leg (instance 1),slow_stop (instance 2)] [exec stop_slowly]",
                "end slow_stop cancelled", "end leg cancelled"}),
            run.recorder.events);
  run.tactics.answer(run.tactics.pending_call("surface"), true);
  ASSERT_TRUE(run.result);
  EXPECT_EQ("aborted", run.result->exit);
}

// Two guards of one net: the first to trip wins, the other stops polling.
TEST(CoralGuards, FirstGuardOfANetToTripWins) {
  GuardRun run(R"(mission m { place begin = 1, w; exit completed, by_leak, by_floor;
      guard leak every 1 { when { system_problem } signal { by_leak } }
      guard floor every 1 { when { altitude_low } signal { by_floor } }
      transition hold { wait { begin } action { TACTIC(EXEC, long_task, w) } }
      transition done { wait { w } signal { completed } } })");
  EXPECT_EQ("long_task sleep(1) sleep(1)", run.tactics.names()) << "guards start in declaration order";
  run.tactics.answer(2, true);  // floor's sleep
  run.tactics.answer(run.tactics.pending_call("altitude_low"), true);
  ASSERT_TRUE(run.result);
  EXPECT_EQ("by_floor", run.result->exit);
  EXPECT_EQ(
      (std::vector<std::string>{"trip floor in m by altitude_low [] [exec long_task,exec sleep]", "end m by_floor"}),
      run.recorder.events)
      << "the leak guard's sleep in flight is forgotten with the rest";
}

TEST(CoralGuards, OnlyGuardsPollingIsAStall) {
  GuardRun run(R"(mission m { place begin = 1, w, never; exit completed, aborted;
      guard leak every 1 { when { system_problem } signal { aborted } }
      transition hold { wait { begin } action { TACTIC(EXEC, short_task, w) } }
      transition done { wait { w, never } signal { completed } } })");
  EXPECT_FALSE(run.result);
  run.tactics.answer(0, true);  // short_task: now only the guard polls
  ASSERT_TRUE(run.result);
  EXPECT_EQ(Outcome::Failed, run.result->outcome);
  EXPECT_TRUE(run.result->stalled);
}

TEST(CoralGuards, AGuardStopsWithItsPhase) {
  GuardRun run(R"(
    net leg { place s = 1; exit ok;
      guard floor every 1 { when { altitude_low } signal { ok } }
      transition go { wait { s } action { TACTIC(EXEC, track, ok) } } }
    mission m { place begin = 1, after; exit completed;
      transition run { wait { begin } action { PHASE(leg, after) } }
      transition next { wait { after } action { TACTIC(EXEC, long_task, completed) } } }
  )");
  EXPECT_EQ("track sleep(1)", run.tactics.names());
  run.tactics.answer(0, true);  // track: the leg ends, its guard with it
  EXPECT_EQ("track sleep(1) long_task", run.tactics.names());
  run.tactics.answer(1, true);  // its sleep, late: ignored, no ask follows
  EXPECT_EQ("track sleep(1) long_task", run.tactics.names());
  run.tactics.answer(2, true);
  ASSERT_TRUE(run.result);
  EXPECT_EQ(Outcome::Completed, run.result->outcome);
}

}  // namespace
}  // namespace strata::strategic
