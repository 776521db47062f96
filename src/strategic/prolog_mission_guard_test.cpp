// Guards in the PROLOG driver (docs/prolog.md §8): the check of guard/4 and
// phase_guard/5 facts at load, each problem at its line; and a trip as the
// rules see it, against a scripted host: unwound to the scope, cleanup run,
// its calls not made, the handler in the scope's place.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "strategic/prolog_mission.h"
#include "strategic/prolog_mission_test_support.h"

namespace strata::strategic {
namespace {

using prolog_mission_testing::PrologMissionTest;
using prolog_mission_testing::Reported;
using prolog_mission_testing::ScriptedHost;
using GuardEvents = std::vector<std::string>;

std::string guard_check_text(const std::string& path) {
  Reported reported;
  auto m = PrologMission::load(path, tactical::Catalogue::builtin(), reported.sources, reported.sink);
  EXPECT_FALSE(m.ok()) << "the rules loaded";
  // Places as the file's name: the folder is the test's temporary one.
  std::string text = reported.text();
  const std::string folder = path.substr(0, path.rfind('/') + 1);
  for (std::size_t at; (at = text.find(folder)) != std::string::npos;) text.erase(at, folder.size());
  return text;
}

bool guard_query_succeeded(prolog::Query::Status s) {
  return s == prolog::Query::Status::True || s == prolog::Query::Status::Last;
}

TEST_F(PrologMissionTest, EveryBadGuardIsAnErrorAtItsLine) {
  const std::string text = guard_check_text(rules_.write("m.pl", R"(:- dynamic complete/1.
guard(leak, 1, [system_problem], on_leak).
guard(leak, 2, [system_problem], on_leak).
guard('Bad'(x), 1, [system_problem], on_leak).
guard(empty, 1, [], on_leak).
guard(args, 1, [altitude_low(3)], on_leak).
guard(unbound, 1, [not(_)], on_leak).
guard(literal, 1, [system_problem], on_leak) :- true, true.
guard(other, 1, [system_problem], lists:append([], [], [])).
guard(nohandler, 1, [system_problem], _).
guard(fast, 0.05, [system_problem], on_leak).
mission :- exec_sleep(1, _).
on_leak :- report(leak).
)"));
  EXPECT_EQ(
      "m.pl:3: error: guard/4: a guard named leak is declared twice for the same scope [PrologCheckError]\n"
      "m.pl:4: error: guard/4: the guard's name must be an atom, not 'Bad'(x) [PrologCheckError]\n"
      "m.pl:5: error: guard empty: the condition must be a non-empty list of ASK primitives, each q or not(q): "
      "[system_problem, not(gps_available)] [PrologCheckError]\n"
      "m.pl:6: error: guard args: altitude_low takes 0 argument(s), not 1 [PrologCheckError]\n"
      "m.pl:7: error: guard unbound: a term of the condition is unbound [PrologCheckError]\n"
      "m.pl:8: error: guard/4 must be a fact: a guard is declared, not computed [PrologCheckError]\n"
      "m.pl:9: error: guard other: the handler lists:append([],[],[]) must be a predicate of the rules, not of "
      "another module [PrologCheckError]\n"
      "m.pl:10: error: guard nohandler: the handler must be a goal, not a variable [PrologCheckError]\n"
      "m.pl:11: error: guard fast: the period is 0.05: it must be a number of seconds from 0.1 to 3600 "
      "[PrologCheckError]\n",
      text);
}

TEST_F(PrologMissionTest, GuardsMustBeStaticAndPhaseGuardsNeedPhases) {
  EXPECT_EQ(
      "m.pl:2: error: guard/4 must not be dynamic: the guards are the facts the rules load (a guard asserted while "
      "they run is never polled) [PrologCheckError]\n",
      guard_check_text(rules_.write("m.pl", R"(:- dynamic guard/4.
guard(leak, 1, [system_problem], report(x)).
mission :- exec_sleep(1, _).
)")));
  EXPECT_EQ(
      "n.pl:1: error: phase_guard/5 guards phases, which are execute_phase/1 calls: the rules define no "
      "execute_phase/1 [PrologCheckError]\n",
      guard_check_text(rules_.write("n.pl", R"(phase_guard(leg, floor, 1, [altitude_low], report(x)).
mission :- exec_sleep(1, _).
)")));
}

TEST_F(PrologMissionTest, GoodGuardsLoadWithoutAWord) {
  auto m = load_ok(rules_.write("m.pl", R"(:- dynamic complete/1, abort/1.
guard(leak, 2, [system_problem], on_leak).
guard(fix, 600, [not(surface_reached), position_uncertain], exec_surface(_)).
phase_guard(leg(N), floor, 0.1, [altitude_low], leg_floor(N)).
phase_guard(leg(N), uncertain, 1, [position_uncertain], leg_floor(N)).
phase_guard(other, floor, 1, [altitude_low], report(other)).
mission :- execute_phase(leg(1)), !.
execute_phase(leg(_)) :- exec_sleep(1, _).
leg_floor(N) :- asserta(abort(leg(N))).
on_leak :- report(leak).
)"));
  EXPECT_TRUE(m);
}

TEST_F(PrologMissionTest, ATripUnwindsToTheScopeRunsTheCleanupAndCallsTheHandler) {
  auto m = load_ok(rules_.write("m.pl", R"(:- dynamic cleaned/0, complete/1.
guard(leak, 2, [system_problem], on_leak).
phase_guard(hold, lost, 5, [not(depth_reached)], report(lost)).
mission :- execute_phase(hold), !, report(after).
execute_phase(hold) :- setup_call_cleanup(true, exec_sleep(60, _), (assertz(cleaned), exec_stop_sonar(_))).
on_leak :- ( cleaned -> report(cleaned) ; report(not_cleaned) ).
)"));
  ASSERT_TRUE(m);
  ScriptedHost host;
  PrologMissionQuery q(*m, host, 100000);
  ASSERT_EQ(prolog::Query::Status::Yield, q.next());
  // The mission's guard trips while the rules wait in the phase's sleep:
  // the phase's scope closes on the way (not tripped), then the mission's.
  host.trip = GuardTripSignal{1, "leak"};
  auto s = q.next();
  ASSERT_NE(prolog::Query::Status::Exception, s) << q.exception_text();
  EXPECT_TRUE(guard_query_succeeded(s));
  EXPECT_EQ((GuardEvents{"guards #1 leak/2 [system_problem]", "phase hold", "guards #2 lost/5 [not depth_reached]",
                         "call sleep 60", "not made stop_sonar", "close #2", "close #1", "report cleaned"}),
            host.events);
}

TEST_F(PrologMissionTest, APhaseGuardsHandlerEndsThePhaseAndTheRulesGoOn) {
  auto m = load_ok(rules_.write("m.pl", R"(:- dynamic complete/1, abort/1.
phase_guard(leg(N), floor, 1, [altitude_low], leg_floor(N)).
mission :- execute_phase(leg(7)), !, report(after).
execute_phase(leg(N)) :- exec_sleep(60, _), asserta(complete(leg(N))).
leg_floor(N) :- report(floor), asserta(abort(leg(N))).
)"));
  ASSERT_TRUE(m);
  ScriptedHost host;
  PrologMissionQuery q(*m, host, 100000);
  ASSERT_EQ(prolog::Query::Status::Yield, q.next());
  host.trip = GuardTripSignal{1, "floor"};
  EXPECT_TRUE(guard_query_succeeded(q.next())) << q.exception_text();
  EXPECT_EQ((GuardEvents{"phase leg(7)", "guards #1 floor/1 [altitude_low]", "call sleep 60", "close #1",
                         "report floor", "end leg(7) abort", "report after"}),
            host.events);
}

}  // namespace
}  // namespace strata::strategic
