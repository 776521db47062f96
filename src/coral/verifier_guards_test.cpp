// Guards under `strata verify` (docs/verification.md, "Guards"): the
// pre-emption is urgent, the guards' polls are not progress, and the two
// properties of a guarded net.
#include <gtest/gtest.h>

#include "coral/analysis.h"
#include "coral/guards.h"
#include "coral/verifier.h"
#include "coral/verifier_test_support.h"
#include "petri/net.h"

namespace strata::coral {
namespace {

using testing::property;
using testing::steps;
using testing::verify_text_mission;
using Status = Property::Status;

constexpr const char* kGuarded = R"(
  net up { place s = 1; exit done;
    transition rise { wait { s } action { TACTIC(EXEC, surface, done) } } }
  mission m {
    place begin = 1, waited, surfaced;
    exit completed, aborted;
    guard leak every 1 { when { system_problem } action { PHASE(up, surfaced) } }
    guard floor every 2 { when { altitude_low, not depth_reached } signal { aborted } }
    transition hold  { wait { begin } action { TACTIC(EXEC, sleep(300), waited) } }
    transition done  { wait { waited } signal { completed } }
    transition close { wait { surfaced } signal { aborted } }
  })";

TEST(VerifierGuards, AGuardedMissionHoldsEveryProperty) {
  VerifyReport r = verify_text_mission(kGuarded);
  ASSERT_EQ(2u, r.nets.size());
  const NetVerification& n = r.nets[1];
  EXPECT_TRUE(n.all_hold()) << verify_text(r);
  EXPECT_EQ("every trip's handler reaches an exit (leak -> aborted; floor -> aborted)",
            property(n, "handlers_end").message);
  EXPECT_EQ(Status::Holds, property(n, "guards_can_trip").status);
  EXPECT_EQ("each of the 3 transitions can fire", property(n, "no_dead").message)
      << "a guard's nodes are not counted among the mission's transitions";
}

TEST(VerifierGuards, NetsWithoutGuardsHaveNoGuardProperties) {
  VerifyReport r = verify_text_mission("mission m { place s = 1; exit e; transition t { wait { s } signal { e } } }");
  for (const Property& p : r.nets[0].properties) EXPECT_NE("guards_can_trip", p.key);
}

// The engine runs a trip, its drops and its handler within the reply that
// tripped it: no other firing and no answer in between. Without urgency,
// `done` could fire after the trip and mark a second exit.
TEST(VerifierGuards, PreemptionIsUrgent) {
  VerifyReport r = verify_text_mission(R"(mission m { place begin = 1, w; exit completed, aborted;
      guard leak every 1 { when { system_problem } signal { aborted } }
      transition hold { wait { begin } action { TACTIC(EXEC, sleep(5), w) } }
      transition done { wait { w } signal { completed } } })");
  EXPECT_EQ(Status::Holds, property(r.nets[0], "exits_exclusive").status) << verify_text(r);
  EXPECT_TRUE(r.ok()) << verify_text(r);
}

TEST(VerifierGuards, WhereOnlyTheGuardsCanPollIsADeadlock) {
  VerifyReport r = verify_text_mission(R"(mission m { place begin = 1, w, never; exit completed, aborted;
      guard leak every 1 { when { system_problem } signal { aborted } }
      transition hold { wait { begin } action { TACTIC(EXEC, sleep(5), w) } }
      transition done { wait { w, never } signal { completed } } })");
  const Property& p = property(r.nets[0], "no_deadlock");
  EXPECT_EQ(Status::Fails, p.status);
  EXPECT_EQ(std::vector<std::string>({"fire hold: EXEC sleep(5)", "EXEC sleep(5) (hold) answers 1 -> w"}), steps(p));
}

// A loop that only a fault can end: a mission must end without a guard.
TEST(VerifierGuards, AnExitReachableOnlyThroughAGuardIsATrap) {
  VerifyReport r = verify_text_mission(R"(mission m { place begin = 1, w; exit completed, aborted;
      guard leak every 1 { when { system_problem } signal { aborted } }
      transition pause { wait { begin } action { TACTIC(EXEC, sleep(5), w) } }
      transition again { wait { w } action { TACTIC(ASK, depth_reached, begin, begin) } } })");
  const Property& p = property(r.nets[0], "can_always_end");
  EXPECT_EQ(Status::Fails, p.status);
  EXPECT_NE(std::string::npos, p.message.find("without a guard tripping")) << p.message;
}

TEST(VerifierGuards, AHandlerThatEndsNowhereFails) {
  VerifyReport r = verify_text_mission(R"(mission m { place begin = 1, w, lost; exit completed, aborted;
      guard leak every 1 { when { system_problem } signal { lost } }
      transition hold { wait { begin } action { TACTIC(EXEC, sleep(5), w) } }
      transition done { wait { w } signal { completed } } })");
  const Property& p = property(r.nets[0], "handlers_end");
  EXPECT_EQ(Status::Fails, p.status);
  ASSERT_TRUE(p.counterexample);
  // The path to the trip from which no exit can be reached.
  EXPECT_EQ("begin:1 leak.cancel:1", p.counterexample->marking);
  EXPECT_EQ("fire leak.trip -> leak.cancel", steps(p).back());
}

// A net in which a transition takes the guard's token away (no CORAL text
// can write it: the names of a guard's places hold a '.'; built by hand
// here) blocks the guard, and the counterexample shows the path to it.
TEST(VerifierGuards, ABlockedGuardIsFoundWithThePathThatBlocksIt) {
  auto c = testing::compile_text(R"(mission m { place begin = 1, w; exit completed, aborted;
      guard leak every 1 { when { system_problem } signal { aborted } }
      transition hold { wait { begin } action { TACTIC(EXEC, sleep(5), w) } }
      transition done { wait { w } signal { completed } } })");
  ASSERT_TRUE(c->program);
  Program program = *c->program;
  CompiledNet& cn = program.nets[0];
  petri::NetBuilder b;
  const petri::Net& old = cn.net;
  for (petri::PlaceId p = 0; p < old.place_count(); ++p) b.add_place(old.place_name(p), old.initial_marking()[p]);
  for (petri::TransitionId t = 0; t < old.transition_count(); ++t) {
    b.add_transition(old.transition_name(t), old.priority(t));
    for (const petri::Arc& a : old.inputs(t)) b.add_input(t, a.node, a.weight);
    for (const petri::Arc& a : old.outputs(t)) b.add_output(t, a.node, a.weight);
  }
  // `steal`: once w is marked, the guard's armed token can go, for ever.
  const petri::TransitionId steal = b.add_transition("steal");
  b.add_input(steal, *old.find_place("leak.armed"));
  b.add_input(steal, *old.find_place("w"));
  b.add_output(steal, *old.find_place("w"));
  cn.net = std::move(b).build();
  cn.actions.emplace_back();
  cn.guard_nodes.emplace_back();
  cn.transition_spans.push_back(cn.span);
  VerifyReport r = verify_program(program);
  const Property& p = property(r.nets[0], "guards_can_trip");
  EXPECT_EQ(Status::Fails, p.status) << verify_text(r);
  EXPECT_EQ("guard leak has stopped polling here, though no guard tripped", p.message);
  ASSERT_TRUE(p.counterexample);
  EXPECT_FALSE(steps(p).empty());
}

TEST(VerifierGuards, TheAnalysisNetForgetsCallsInFlightWhenAGuardTrips) {
  auto c = testing::compile_text(kGuarded);
  ASSERT_TRUE(c->program);
  const CompiledNet& cn = *c->program->find("m");
  AnalysisNet an = build_analysis_net(*c->program, cn);
  ASSERT_TRUE(an.net.find_transition("leak.drop.hold.sleep").has_value());
  ASSERT_TRUE(an.net.find_transition("leak.drop.floor.poll.sleep").has_value()) << "the other guard's poll too";
  EXPECT_FALSE(an.net.find_transition("leak.drop.leak.poll.sleep").has_value()) << "not its own";
  const petri::TransitionId d = *an.net.find_transition("leak.drop.hold.sleep");
  EXPECT_TRUE(an.urgent.at(d));
  EXPECT_EQ(kGuardDropPriority, an.net.priority(d));
  EXPECT_FALSE(an.urgent.at(*an.net.find_transition("hold")));
}

}  // namespace
}  // namespace strata::coral
