// Guards in PROLOG missions (docs/prolog.md §8) against a scripted Tactical
// level: pre-emption in a blocking call, in a nested phase, of another
// guard's handler; cleanup; catch-alls; the handler's end; polls that keep
// nothing alive.
#include "strategic/prolog_executor_test_support.h"

namespace strata::strategic::prolog_testing {
namespace {

// What the guard tests look at: calls with their guard, trips, phase ends.
struct PrologGuardRecorder final : Observer {
  void action_started(const ActionStart& e) override {
    events.push_back(
        fmt::format("{} {}{}", e.kind_name(), e.primitive, e.guard.empty() ? "" : " [" + std::string(e.guard) + "]"));
  }
  void phase_started(const PhaseStart& e) override { events.push_back(fmt::format("start {}#{}", e.name, e.instance)); }
  void phase_ended(const PhaseEnd& e) override {
    events.push_back(e.cancelled ? fmt::format("end {}#{} cancelled", e.name, e.instance)
                                 : fmt::format("end {}#{} {}", e.name, e.instance, e.exit));
  }
  void guard_tripped(const GuardTrip& e) override {
    std::string phases, calls;
    for (const auto& p : e.preempted_phases) phases += (phases.empty() ? "" : ", ") + p;
    for (const auto& c : e.preempted_calls) calls += (calls.empty() ? "" : ", ") + c;
    events.push_back(fmt::format("TRIP {} of {}#{} on {} at {:.1f}: phases [{}] calls [{}]", e.guard, e.net, e.instance,
                                 e.condition, e.sim_time_s, phases, calls));
  }
  void notice(const Notice& e) override { notices.push_back(e.text); }
  Strings events;
  Strings notices;
};

class PrologGuardTest : public PrologExecutorTest {
 protected:
  struct Run {
    std::unique_ptr<Session> session;
    PrologGuardRecorder guards;
    FakeTactics& tactics() { return session->tactics; }
  };
  std::unique_ptr<Run> start(const std::string& name, const std::string& text) {
    missions_.push_back(rules(name, text));
    if (!missions_.back()) return nullptr;
    auto run = std::make_unique<Run>();
    run->session = std::make_unique<Session>(*missions_.back());
    run->session->executor->add_observer(run->guards);
    run->session->start();
    return run;
  }
  // Answers the oldest pending call written `call` ("sleep(2)",
  // "system_problem") at simulated time t.
  static void reply(Run& run, const std::string& call, bool value, double t) {
    FakeTactics& f = run.tactics();
    for (std::size_t i : f.pending) {
      std::string written = f.calls[i].name;
      for (std::size_t k = 0; k < f.calls[i].args.size(); ++k) {
        written += (k == 0 ? "(" : ",") + tactical::to_string(f.calls[i].args[k]);
      }
      if (!f.calls[i].args.empty()) written += ')';
      if (written != call) continue;
      f.time_s = t;
      f.take(i)(tactical::CallOutcome{value, t});
      return;
    }
    ADD_FAILURE() << "no pending call " << call << " among: " << f.names();
  }
};

constexpr const char* kGuardAbortFacts = R"(
:- dynamic current_phase/1, complete/1, abort/1.
current_phase(run).
give_up :- retract(current_phase(_)), assertz(current_phase(mission_abort)).
)";

TEST_F(PrologGuardTest, ATripInABlockingCallPreemptsItAndTheHandlerRunsInPlaceOfTheMission) {
  auto r = start("blocking", std::string(kGuardAbortFacts) + R"(
guard(leak, 2, [system_problem, altitude_low], on_leak).
mission :- exec_sleep(120, _), report(never).
on_leak :- report(leaking), give_up, exec_surface(_).
)");
  ASSERT_TRUE(r);
  // The guard's sleep right after the mission's first call.
  EXPECT_EQ("sleep(120) sleep(2)", r->tactics().names());
  reply(*r, "sleep(2)", true, 2.0);
  reply(*r, "system_problem", false, 2.1);
  reply(*r, "altitude_low", false, 2.2);  // no term held: sleep again at once
  reply(*r, "sleep(2)", true, 4.2);
  reply(*r, "system_problem", true, 4.3);  // trips: altitude_low is not asked
  EXPECT_EQ("sleep(120) sleep(2) system_problem altitude_low sleep(2) system_problem report(leaking) surface",
            r->tactics().names());
  EXPECT_EQ((Strings{"exec sleep", "exec sleep [leak]", "ask system_problem [leak]", "ask altitude_low [leak]",
                     "exec sleep [leak]", "ask system_problem [leak]",
                     "TRIP leak of blocking#0 on system_problem at 4.3: phases [] calls [exec sleep]", "report report",
                     "exec surface"}),
            Strings(r->guards.events.begin() + 1, r->guards.events.end()));
  reply(*r, "surface", true, 4.4);
  ASSERT_TRUE(r->session->ended_with(Outcome::Aborted)) << r->session->why();
  // The pre-empted sleep's reply comes late: ignored, without a word.
  reply(*r, "sleep(120)", true, 120.0);
  EXPECT_TRUE(r->guards.notices.empty()) << r->guards.notices[0];
  EXPECT_EQ(8u, r->tactics().calls.size());
}

TEST_F(PrologGuardTest, GuardsStartInDeclarationOrderAndTheFirstToTripWins) {
  auto r = start("two", std::string(kGuardAbortFacts) + R"(
guard(clock, 1, [time_out], on_clock).
guard(deep, 3, [not(depth_reached)], on_deep).
mission :- exec_sleep(120, _).
on_clock :- report(clock).
on_deep :- report(deep).
)");
  ASSERT_TRUE(r);
  EXPECT_EQ("sleep(120) sleep(1) sleep(3)", r->tactics().names());
  reply(*r, "sleep(1)", true, 1.0);
  reply(*r, "sleep(3)", true, 3.0);
  // depth_reached answered 0: `not depth_reached` holds; clock's ask is in flight.
  reply(*r, "depth_reached", false, 3.1);
  EXPECT_EQ("sleep(120) sleep(1) sleep(3) time_out depth_reached report(deep)", r->tactics().names());
  EXPECT_EQ("TRIP deep of two#0 on not depth_reached at 3.1: phases [] calls [exec sleep, ask time_out]",
            r->guards.events[r->guards.events.size() - 3]);
  ASSERT_TRUE(r->session->ended_with(Outcome::Completed)) << r->session->why();
  reply(*r, "time_out", true, 3.2);  // the other guard stopped: its late answer trips nothing
  EXPECT_EQ(6u, r->tactics().calls.size());
}

TEST_F(PrologGuardTest, APhaseGuardPreemptsANestedPhaseAndItsHandlerEndsThePhase) {
  auto r = start("nested", std::string(kGuardAbortFacts) + R"(
phase_guard(leg(N), floor, 1, [altitude_low], leg_floor(N)).
mission :- execute_phase(leg(1)), !, ( abort(leg(1)) -> exec_surface(_) ; true ).
execute_phase(leg(N)) :- exec_track(0, 0, 10, 0, _), execute_phase(scan(N)), !, asserta(complete(leg(N))).
execute_phase(scan(_)) :- exec_sleep(60, _).
leg_floor(N) :- report(floor), asserta(abort(leg(N))).
)");
  ASSERT_TRUE(r);
  EXPECT_EQ("track(0,0,10,0) sleep(1)", r->tactics().names());
  reply(*r, "track(0,0,10,0)", true, 0.1);
  reply(*r, "sleep(1)", true, 1.1);
  reply(*r, "altitude_low", true, 1.2);
  EXPECT_EQ((Strings{"start nested#0", "start leg(1)#1", "exec track", "exec sleep [floor]", "start scan(1)#2",
                     "exec sleep", "ask altitude_low [floor]",
                     "TRIP floor of leg(1)#1 on altitude_low at 1.2: phases [scan(1) (instance 2)] calls [exec sleep]",
                     "end scan(1)#2 cancelled", "report report", "end leg(1)#1 abort", "exec surface"}),
            r->guards.events);
  reply(*r, "surface", true, 1.3);
  ASSERT_TRUE(r->session->ended_with(Outcome::Completed)) << r->session->why();
  EXPECT_EQ((Strings{"end nested#0 '' 0", "mission_ended completed", "on_end"}), r->session->last(3));
}

TEST_F(PrologGuardTest, AMissionGuardPreemptsThePhaseGuardsHandlerOuterWins) {
  auto r = start("outer", std::string(kGuardAbortFacts) + R"(
guard(leak, 2, [system_problem], on_leak).
phase_guard(leg, floor, 1, [altitude_low], leg_floor).
mission :- execute_phase(leg), !.
execute_phase(leg) :- exec_track(0, 0, 10, 0, _).
leg_floor :- exec_surface(_), exec_sleep(30, _).
on_leak :- report(leak), give_up.
)");
  ASSERT_TRUE(r);
  // The enclosing scope's sleep first.
  EXPECT_EQ("track(0,0,10,0) sleep(2) sleep(1)", r->tactics().names());
  reply(*r, "sleep(1)", true, 1.0);
  reply(*r, "altitude_low", true, 1.1);  // floor trips: its handler runs in the leg
  reply(*r, "surface", true, 1.2);
  reply(*r, "sleep(2)", true, 2.0);  // leak still polls beside the handler
  reply(*r, "system_problem", true, 2.1);
  EXPECT_EQ("track(0,0,10,0) sleep(2) sleep(1) altitude_low surface sleep(30) system_problem report(leak)",
            r->tactics().names());
  Strings trips;
  for (const auto& e : r->guards.events) {
    if (e.starts_with("TRIP") || e.starts_with("end")) trips.push_back(e);
  }
  EXPECT_EQ((Strings{"TRIP floor of leg#1 on altitude_low at 1.1: phases [] calls [exec track]",
                     "TRIP leak of outer#0 on system_problem at 2.1: phases [leg (instance 1)] calls [exec sleep]",
                     "end leg#1 cancelled", "end outer#0 mission_abort"}),
            trips);
  ASSERT_TRUE(r->session->ended_with(Outcome::Aborted)) << r->session->why();
}

TEST_F(PrologGuardTest, ATripRunsTheCleanupButItsCallsAreNotMade) {
  auto r = start("cleanup", R"(
:- dynamic cleaned/0.
guard(leak, 1, [system_problem], on_leak).
mission :- setup_call_cleanup(true, exec_sleep(60, _), (assertz(cleaned), exec_stop_sonar(_))).
on_leak :- ( cleaned -> report(cleaned) ; report(not_cleaned) ).
)");
  ASSERT_TRUE(r);
  reply(*r, "sleep(1)", true, 1.0);
  reply(*r, "system_problem", true, 1.1);
  EXPECT_EQ("sleep(60) sleep(1) system_problem report(cleaned)", r->tactics().names());
  ASSERT_EQ(1u, r->guards.notices.size());
  EXPECT_EQ(
      "exec stop_sonar was not called: guard leak has tripped, and nothing reaches the vehicle before its handler "
      "runs (a call in a cleanup handler, or after a catch of the trip)",
      r->guards.notices[0]);
  ASSERT_TRUE(r->session->ended_with(Outcome::Completed)) << r->session->why();
}

TEST_F(PrologGuardTest, RulesThatCatchTheTripCannotGoOnTheHandlerRunsAllTheSame) {
  auto r = start("catcher", R"(
guard(leak, 1, [system_problem], on_leak).
mission :- catch(exec_sleep(60, _), _, true), catch(exec_surface(_), _, true), report(went_on).
on_leak :- report(handled).
)");
  ASSERT_TRUE(r);
  reply(*r, "sleep(1)", true, 1.0);
  reply(*r, "system_problem", true, 1.1);
  EXPECT_EQ("sleep(60) sleep(1) system_problem report(handled)", r->tactics().names());
  EXPECT_EQ(2u, r->guards.notices.size()) << "exec surface and report went_on were not made";
  ASSERT_TRUE(r->session->ended_with(Outcome::Completed)) << r->session->why();
}

TEST_F(PrologGuardTest, AHandlerThatFailsFailsTheMission) {
  auto r = start("handler_fails", R"(
guard(leak, 1, [system_problem], on_leak).
mission :- exec_sleep(60, _).
on_leak :- ask_surface_reached(1).
)");
  ASSERT_TRUE(r);
  reply(*r, "sleep(1)", true, 1.0);
  reply(*r, "system_problem", true, 1.1);
  reply(*r, "surface_reached", false, 1.2);
  ASSERT_TRUE(r->session->ended_with(Outcome::Failed));
  EXPECT_EQ("the handler of guard leak failed", r->session->why());
}

TEST_F(PrologGuardTest, PollsKeepNothingAliveTheMissionEndsWithItsRules) {
  auto r = start("short", R"(
guard(leak, 1, [system_problem], on_leak).
mission :- exec_sleep(5, _).
on_leak :- report(leak).
)");
  ASSERT_TRUE(r);
  reply(*r, "sleep(1)", true, 1.0);
  reply(*r, "system_problem", false, 1.1);
  reply(*r, "sleep(5)", true, 5.0);  // the rules end: the guard's sleep is still in flight
  ASSERT_TRUE(r->session->ended_with(Outcome::Completed)) << r->session->why();
  EXPECT_FALSE(r->session->executor->running());
  reply(*r, "sleep(1)", true, 2.1);
  EXPECT_EQ("sleep(5) sleep(1) system_problem sleep(1)", r->tactics().names()) << "nothing issued after the end";
  EXPECT_TRUE(r->guards.notices.empty());
}

TEST_F(PrologGuardTest, AFailedPollFailsTheMission) {
  auto r = start("lost", R"(
guard(leak, 1, [system_problem], on_leak).
mission :- exec_sleep(60, _).
on_leak :- report(leak).
)");
  ASSERT_TRUE(r);
  FakeTactics& f = r->tactics();
  f.take(1)(tactical::CallError{tactical::CallError::Kind::LinkLost, std::nullopt, "the link closed"});
  ASSERT_TRUE(r->session->ended_with(Outcome::Failed));
  EXPECT_EQ("exec sleep failed: the link closed", r->session->why());
  EXPECT_EQ(tactical::CallError::Kind::LinkLost, r->session->result->call_error);
}

TEST_F(PrologGuardTest, AScopeWithoutACallNeverPolls) {
  auto r = start("quiet", R"(
:- dynamic complete/1.
phase_guard(talk, chatter, 1, [system_problem], report(x)).
mission :- execute_phase(talk), !, exec_sleep(1, _).
execute_phase(talk) :- report(hello), asserta(complete(talk)).
)");
  ASSERT_TRUE(r);
  EXPECT_EQ("report(hello) sleep(1)", r->tactics().names());
}

}  // namespace
}  // namespace strata::strategic::prolog_testing
