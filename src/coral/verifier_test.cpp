#include "coral/verifier.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "coral/analysis.h"
#include "coral/export.h"
#include "coral/test_support.h"
#include "coral/verifier_test_support.h"
#include "coral/verify_report.h"
#include "core/memory.h"
#include "petri/dump.h"
#include "petri/pnml.h"

namespace strata::coral {
namespace {

using testing::compile_text;
using testing::property;
using testing::steps;
using testing::verify_text_mission;
using Status = Property::Status;

TEST(AnalysisNet, EachWaitingActionGetsAnInFlightPlaceAndItsOutcomes) {
  auto c = compile_text(
      "net n { place s = 1, a, b, r; exit e;\n"
      "  transition ask { wait { s } action { TACTIC(ASK, depth_reached, a, b) } }\n"
      "  transition go { wait { a } action { TACTIC(REPORT, \"hi\"), TACTIC(EXEC, sleep(1), r), TACTIC(EXEC, sleep(2), "
      "r) } }\n"
      "  transition end { wait { r*2 } signal { e } }\n"
      "  transition other { wait { b } signal { e } } }");
  ASSERT_TRUE(c->program);
  AnalysisNet an = build_analysis_net(*c->program, c->program->nets[0]);
  EXPECT_EQ(
      "place s = 1\nplace a = 0\nplace b = 0\nplace r = 0\nplace e = 0\n"
      "place ask.depth_reached = 0\nplace go.sleep = 0\nplace go.sleep.2 = 0\n"
      "transition ask: in{s} out{ask.depth_reached}\n"
      "transition go: in{a} out{go.sleep, go.sleep.2}\n"
      "transition end: in{r*2} out{e}\n"
      "transition other: in{b} out{e}\n"
      "transition ask.depth_reached.yes: in{ask.depth_reached} out{a}\n"
      "transition ask.depth_reached.no: in{ask.depth_reached} out{b}\n"
      "transition go.sleep.done: in{go.sleep} out{r}\n"
      "transition go.sleep.2.done: in{go.sleep.2} out{r}\n",
      petri::dump_net(an.net));
}

TEST(Verifier, ASequentialPhaseHoldsEveryProperty) {
  VerifyReport r = verify_text_mission(
      "net n { place s = 1, a, b; exit done, failed;\n"
      "  transition ask { wait { s } action { TACTIC(ASK, q, a, b) } }\n"
      "  transition yes { wait { a } action { TACTIC(EXEC, sleep(1), done) } }\n"
      "  transition no { wait { b } signal { failed } } }");
  ASSERT_EQ(1u, r.nets.size());
  const NetVerification& n = r.nets[0];
  EXPECT_TRUE(r.ok()) << verify_text(r);
  EXPECT_EQ(7u, n.states);  // s, in flight, a, b, sleeping, done, failed
  EXPECT_EQ(std::vector<bool>({true, true}), n.exit_reachable);
  ASSERT_EQ(1u, n.invariants.size());
  EXPECT_EQ(1u, n.invariants[0].constant);
  EXPECT_TRUE(n.uncovered.empty());
}

TEST(Verifier, ADeadlockShowsTheShortestSequenceInTheMissionsNames) {
  VerifyReport r = verify_text_mission(
      "net n { place s = 1, ok, stuck; exit e;\n"
      "  transition ask { wait { s } action { TACTIC(ASK, depth_reached, ok, stuck) } }\n"
      "  transition fine { wait { ok } signal { e } } }");
  const Property& p = property(r.nets[0], "no_deadlock");
  EXPECT_EQ(Status::Fails, p.status);
  EXPECT_EQ(std::vector<std::string>({"fire ask: ASK depth_reached", "ASK depth_reached (ask) answers 0 -> stuck"}),
            steps(p));
  EXPECT_EQ("stuck:1", p.counterexample->marking);
  EXPECT_FALSE(r.ok());
  // The same marking cannot end either.
  EXPECT_EQ(Status::Fails, property(r.nets[0], "can_always_end").status);
}

TEST(Verifier, ATrapThatKeepsFiringIsNamedWithWhatCycles) {
  VerifyReport r = verify_text_mission(
      "net n { place s = 1, ok, spin; exit e;\n"
      "  transition ask { wait { s } action { TACTIC(ASK, q, ok, spin) } }\n"
      "  transition fine { wait { ok } signal { e } }\n"
      "  transition loop { wait { spin } action { TACTIC(EXEC, sleep(1), spin) } } }");
  const NetVerification& n = r.nets[0];
  EXPECT_EQ(Status::Holds, property(n, "no_deadlock").status);
  const Property& p = property(n, "can_always_end");
  EXPECT_EQ(Status::Fails, p.status);
  EXPECT_EQ(
      "trapped: from here an exit can no longer be reached; only EXEC sleep(1) answering 1, loop can still happen",
      p.message);
  EXPECT_EQ(std::vector<std::string>({"fire ask: ASK q", "ASK q (ask) answers 0 -> spin"}), steps(p));
}

TEST(Verifier, TheTrapShownIsTheNearest) {
  VerifyReport r = verify_text_mission(
      "net n { place s = 1, ok, spin, dead; exit e;\n"
      "  transition dead_end { wait { s } signal { dead } }\n"
      "  transition ask { wait { s } action { TACTIC(ASK, q, ok, spin) } }\n"
      "  transition fine { wait { ok } signal { e } }\n"
      "  transition loop { wait { spin } action { TACTIC(EXEC, sleep(1), spin) } } }");
  const Property& p = property(r.nets[0], "can_always_end");
  EXPECT_EQ(std::vector<std::string>({"fire dead_end -> dead"}), steps(p));
}

TEST(Verifier, TwoExitsMarkedTogether) {
  VerifyReport r = verify_text_mission(
      "net n { place s = 1; exit complete, abort;\n"
      "  transition both { wait { s } signal { complete, abort } } }");
  const Property& p = property(r.nets[0], "exits_exclusive");
  EXPECT_EQ(Status::Fails, p.status);
  EXPECT_EQ("exits complete, abort are marked together (the engine takes the first declared)", p.message);
  EXPECT_EQ(std::vector<std::string>({"fire both -> complete, abort"}), steps(p));
}

TEST(Verifier, AnUnboundedPlaceIsShownWithTheStepsThatRepeat) {
  VerifyReport r = verify_text_mission(
      "net n { place s = 1, heap, ok; exit e;\n"
      "  transition ask { wait { s } action { TACTIC(ASK, q, ok, s) } signal { heap } }\n"
      "  transition fine { wait { ok } signal { e } } }");
  const NetVerification& n = r.nets[0];
  const Property& p = property(n, "bounded");
  EXPECT_EQ(Status::Fails, p.status);
  EXPECT_EQ("unbounded: heap can grow without limit; the steps from step 1 on can repeat for ever", p.message);
  EXPECT_EQ(std::vector<std::string>({"fire ask: ASK q -> heap", "ASK q (ask) answers 0 -> s"}), steps(p));
  EXPECT_EQ(std::optional<std::size_t>(0), p.counterexample->repeat_from);
  EXPECT_FALSE(n.complete);
  // What needs the whole graph is not decided; what was seen still counts.
  EXPECT_EQ(Status::Undecided, property(n, "can_always_end").status);
  EXPECT_EQ(std::vector<std::string>({"heap"}), n.uncovered);
  EXPECT_EQ(Status::Fails, property(n, "one_safe").status);
}

// Regression: a new marking with an exit marked was taken for a repeat.
TEST(Verifier, AMarkingThatEndsAtAnExitIsNoSignOfUnboundedness) {
  VerifyReport r = verify_text_mission(
      "mission m { place a = 1; exit done;\n"
      "  transition t { wait { a } signal { a, done } } }");
  EXPECT_EQ(Status::Holds, property(r.nets[0], "bounded").status) << verify_text(r);
  EXPECT_TRUE(r.nets[0].complete);
}

// Regression: a state left half-expanded by a token overflow was a deadlock.
TEST(Verifier, ATokenOverflowLeavesPropertiesUndecidedNotFailed) {
  VerifyReport r = verify_text_mission(
      "mission m { place a = 4294967295, b = 4294967295; exit done;\n"
      "  transition t { wait { a } signal { b } }\n"
      "  transition fin { wait { b } signal { done } } }");
  const NetVerification& n = r.nets[0];
  EXPECT_FALSE(n.complete);
  EXPECT_NE(std::string::npos, n.stopped_why.find("more than 4294967295 tokens")) << n.stopped_why;
  EXPECT_EQ(Status::Undecided, property(n, "no_deadlock").status) << verify_text(r);
}

// Regression: every new marking walked its whole path back to the start.
TEST(Verifier, ALongCountdownIsExploredInFull) {
  VerifyReport r = verify_text_mission(
      "mission m { place a = 20000, b; exit done;\n"
      "  transition t { wait { a } signal { b } }\n"
      "  transition fin { wait { b*20000 } signal { done } } }");
  EXPECT_TRUE(r.nets[0].complete);
  EXPECT_EQ(20002u, r.nets[0].states);
  EXPECT_EQ(Status::Holds, property(r.nets[0], "bounded").status);
}

// Regression: 2^20 minimal P-semiflows took minutes to enumerate.
TEST(Verifier, TooManySemiflowsAreCutShort) {
  std::string text = "mission m { place a0 = 1";
  for (int i = 0; i < 20; ++i) text += fmt::format(", b{0}, c{0}, a{1}", i, i + 1);
  text += "; exit done;\n";
  for (int i = 0; i < 20; ++i) {
    text += fmt::format("  transition f{0} {{ wait {{ a{0} }} signal {{ b{0}, c{0} }} }}\n", i);
    text += fmt::format("  transition j{0} {{ wait {{ b{0}, c{0} }} signal {{ a{1} }} }}\n", i, i + 1);
  }
  text += "  transition fin { wait { a20 } signal { done } } }";
  VerifyReport r = verify_text_mission(text);
  EXPECT_FALSE(r.nets[0].invariants_complete);
  EXPECT_TRUE(r.ok()) << verify_text(r);
}

TEST(Verifier, ACycleOfFiringsWithoutActionsIsABusyCycle) {
  VerifyReport r = verify_text_mission(
      "mission m { place a = 1, b; exit done;\n"
      "  transition t1 { wait { a } signal { b } }\n"
      "  transition t2 { wait { b } signal { a } }\n"
      "  transition t3 priority -1 { wait { a } signal { done } } }");
  const Property& p = property(r.nets[0], "no_busy_cycle");
  EXPECT_EQ(Status::Fails, p.status);
  EXPECT_EQ(
      "busy cycle: t1, t2 can fire for ever without waiting for the vehicle, from step 1 on (the engine stops such a "
      "mission after its firing limit)",
      p.message);
  EXPECT_EQ(std::vector<std::string>({"fire t1 -> b", "fire t2 -> a"}), steps(p));
  EXPECT_EQ(std::optional<std::size_t>(0), p.counterexample->repeat_from);
  // A loop that waits for the vehicle on every round is not busy.
  VerifyReport polling = verify_text_mission(
      "mission m { place a = 1, b; exit done;\n"
      "  transition ask { wait { a } action { TACTIC(ASK, q, done, b) } }\n"
      "  transition again { wait { b } signal { a } } }");
  EXPECT_EQ(Status::Holds, property(polling.nets[0], "no_busy_cycle").status) << verify_text(polling);
}

TEST(Verifier, APhaseWithoutExitsCanNeverEnd) {
  VerifyReport r = verify_text_mission("net forever { place a = 1, b; transition t { wait { a } signal { b } } }");
  const NetVerification& n = r.nets[0];
  EXPECT_EQ(Status::Fails, property(n, "no_deadlock").status);
  EXPECT_EQ("a phase without exits can never end", property(n, "can_always_end").message);
}

TEST(Verifier, TwoTokensInAPlaceBreakOneSafety) {
  VerifyReport r = verify_text_mission(
      "net n { place s = 1, a; exit e;\n"
      "  transition split { wait { s } signal { a*2 } }\n"
      "  transition join { wait { a*2 } signal { e } } }");
  const Property& p = property(r.nets[0], "one_safe");
  EXPECT_EQ(Status::Fails, p.status);
  EXPECT_EQ("a can hold 2 tokens", p.message);
  EXPECT_EQ(std::vector<std::string>({"fire split -> a"}), steps(p));
  EXPECT_EQ(Status::Holds, property(r.nets[0], "bounded").status);
}

// A chain mission of n places, as scripts/chain-mission writes it.

}  // namespace
}  // namespace strata::coral
