#include "coral/verifier.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "coral/analysis.h"
#include "coral/export.h"
#include "coral/test_support.h"
#include "coral/verify_report.h"
#include "core/memory.h"
#include "petri/dump.h"
#include "petri/pnml.h"

namespace strata::coral {
namespace {

using testing::compile_text;
using Status = Property::Status;

const Property& property(const NetVerification& n, std::string_view key) {
  for (const auto& p : n.properties) {
    if (p.key == key) return p;
  }
  throw std::runtime_error("no property " + std::string(key));
}

std::vector<std::string> steps(const Property& p) {
  std::vector<std::string> out;
  if (p.counterexample) {
    for (const auto& s : p.counterexample->steps) out.push_back(step_text(s));
  }
  return out;
}

VerifyReport verify_text_mission(const std::string& text,
                                 const std::vector<std::pair<std::string, std::string>>& extra = {}) {
  auto c = compile_text(text, extra);
  if (!c->program) {
    std::string all;
    for (const auto& k : c->kinds()) all += k + "\n";
    ADD_FAILURE() << "does not compile:\n" << all;
    return {};
  }
  return verify_program(*c->program);
}

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
std::string chain_mission(std::size_t n) {
  std::string text = "mission chain { place p0 = 1";
  for (std::size_t i = 1; i < n; ++i) text += fmt::format(", p{}", i);
  text += ";\n";
  for (std::size_t i = 0; i + 1 < n; ++i)
    text += fmt::format("  transition t{} {{ wait {{ p{} }} signal {{ p{} }} }}\n", i, i, i + 1);
  return text + "}\n";
}

bool nothing_fails(const NetVerification& n) {
  return std::none_of(n.properties.begin(), n.properties.end(),
                      [](const Property& p) { return p.status == Status::Fails; });
}

// Regression: a 10,000-place chain took 3.1 GB in the P-semiflow step
// whatever --max-states said, and was said to have "too many minimal
// P-semiflows" where it has exactly one.
TEST(Verifier, AChainOfTenThousandPlacesHasItsOneSemiflowWithinTheStateLimit) {
  auto c = compile_text(chain_mission(10'000));
  ASSERT_TRUE(c->program);
  VerifyOptions o;
  o.max_states = 100;
  VerifyReport r = verify_program(*c->program, o);
  ASSERT_EQ(1u, r.nets.size());
  const NetVerification& n = r.nets[0];
  EXPECT_FALSE(n.complete);
  EXPECT_TRUE(nothing_fails(n)) << verify_text(r);
  ASSERT_TRUE(n.invariants_complete) << n.invariants_skipped;
  ASSERT_EQ(1u, n.invariants.size());
  EXPECT_EQ(10'000u, n.invariants[0].weights.size());
  EXPECT_EQ(1u, n.invariants[0].constant);
  EXPECT_TRUE(n.uncovered.empty());
}

// Regression: the memory limit did not bound the mission's analysis steps.
// A limit just above what the process holds stops the graph early: what it
// did not settle is not decided, never failed.
TEST(Verifier, AMemoryLimitLeavesPropertiesUndecidedNeverFailed) {
  auto c = compile_text(chain_mission(2'000));
  ASSERT_TRUE(c->program);
  VerifyOptions o;
  o.max_memory_bytes = core::resident_bytes() + (std::size_t{1} << 20);
  VerifyReport r = verify_program(*c->program, o);
  const NetVerification& n = r.nets[0];
  EXPECT_FALSE(n.complete);
  EXPECT_NE(std::string::npos, n.stopped_why.find("over the memory limit")) << n.stopped_why;
  EXPECT_LT(n.states, 2'000u);
  EXPECT_TRUE(nothing_fails(n)) << verify_text(r);
  EXPECT_EQ(Status::Undecided, property(n, "can_always_end").status);
  EXPECT_FALSE(r.ok());
}

TEST(Verifier, ATimeLimitLeavesPropertiesUndecidedNeverFailed) {
  auto c = compile_text(chain_mission(3'000));
  ASSERT_TRUE(c->program);
  VerifyOptions o;
  o.time_limit_s = 1e-9;
  VerifyReport r = verify_program(*c->program, o);
  const NetVerification& n = r.nets[0];
  EXPECT_TRUE(nothing_fails(n)) << verify_text(r);
  EXPECT_EQ(Status::Undecided, property(n, "can_always_end").status);
  EXPECT_FALSE(r.ok());
}

// Regression: `strata run` refused any mission whose places may hold two
// tokens (one_safe) or with a dead transition; those are warnings now.
TEST(Verifier, OneSafetyAndDeadTransitionsAreWarningsThatDoNotBlockARun) {
  VerifyReport r = verify_text_mission(
      "mission counting { place bolts = 4, nuts = 4, pairs, spare;\n"
      "  exit done;\n"
      "  transition pair { wait { bolts, nuts } signal { pairs } }\n"
      "  transition finish { wait { pairs*4 } signal { done } }\n"
      "  transition never { wait { spare } signal { done } } }");
  const NetVerification& n = r.nets[0];
  EXPECT_EQ(Status::Fails, property(n, "one_safe").status);
  EXPECT_FALSE(property(n, "one_safe").blocking);
  EXPECT_EQ(Status::Fails, property(n, "no_dead").status);
  EXPECT_FALSE(property(n, "no_dead").blocking);
  EXPECT_TRUE(property(n, "no_deadlock").blocking);
  EXPECT_TRUE(r.ok()) << verify_text(r);
  EXPECT_FALSE(r.all_hold());
  EXPECT_NE(std::string::npos, verify_text(r).find("  warn  one_safe ")) << verify_text(r);
}

// Regression: 70 nested phases passed verify and failed at run ("would nest
// phases 65 deep (limit 64)").
TEST(Verifier, PhasesNestedPastTheEnginesLimitFailPhaseDepth) {
  std::string text;
  constexpr std::size_t kDepth = 70;
  for (std::size_t i = 0; i < kDepth; ++i) {
    text += i + 1 < kDepth
                ? fmt::format(
                      "net ph{} {{ place s = 1, back; exit done;\n"
                      "  transition go {{ wait {{ s }} action {{ PHASE(ph{}, back) }} }}\n"
                      "  transition up {{ wait {{ back }} signal {{ done }} }} }}\n",
                      i, i + 1)
                : fmt::format(
                      "net ph{} {{ place s = 1; exit done; transition go {{ wait {{ s }} signal {{ done }} }} }}\n", i);
  }
  text +=
      "mission deep { place begin = 1, back; exit closed;\n"
      "  transition go { wait { begin } action { PHASE(ph0, back) } }\n"
      "  transition end { wait { back } signal { closed } } }\n";
  auto c = compile_text(text);
  ASSERT_TRUE(c->program);
  VerifyOptions o;
  o.mission_only = true;
  VerifyReport r = verify_program(*c->program, o);
  ASSERT_EQ(kDepth + 1, r.nets.size());
  const NetVerification& mission = r.nets.back();
  const Property& p = property(mission, "phase_depth");
  EXPECT_EQ(Status::Fails, p.status);
  EXPECT_TRUE(p.blocking);
  EXPECT_EQ(
      "would nest phases 70 deep, past the engine's limit of 64 (deep -> ph0 -> ph1 -> ph2 -> ... 64 more ... -> "
      "ph67 -> ph68 -> ph69)",
      p.message);
  EXPECT_FALSE(r.ok());
  // Phases come callees first (ph69 ... ph0). A phase runs at depth 1 at
  // least: ph5 calls 64 more (65 deep), ph6 calls 63 (64 deep, the limit).
  EXPECT_EQ(Status::Fails, property(r.nets[kDepth - 1 - 5], "phase_depth").status);
  EXPECT_EQ("phases nest at most 64 deep (the engine's limit: 64)",
            property(r.nets[kDepth - 1 - 6], "phase_depth").message);
}

TEST(Verifier, ADeadTransitionSaysWhichInputIsNeverMarked) {
  VerifyReport r = verify_text_mission(
      "net n { place s = 1, never; exit e;\n"
      "  transition go { wait { s } signal { e } }\n"
      "  transition unused { wait { never } signal { e } } }");
  const Property& p = property(r.nets[0], "no_dead");
  EXPECT_EQ(Status::Fails, p.status);
  EXPECT_EQ("never fires: unused (never is never marked)", p.message);
  EXPECT_FALSE(p.counterexample.has_value());
}

TEST(Verifier, APhaseThatCannotAbortMakesTheCallersAbortBranchDead) {
  VerifyReport r = verify_text_mission(
      "net p { place s = 1; exit complete, abort;\n"
      "  transition go { wait { s } action { TACTIC(EXEC, sleep(1), complete) } } }\n"
      "mission m { place begin = 1, fine, bad; exit closed;\n"
      "  transition run { wait { begin } action { PHASE(p, fine, bad) } }\n"
      "  transition end { wait { fine } signal { closed } }\n"
      "  transition recover { wait { bad } signal { closed } } }");
  ASSERT_EQ(2u, r.nets.size());
  EXPECT_EQ("p", r.nets[0].name);  // phases first
  EXPECT_EQ(std::vector<bool>({true, false}), r.nets[0].exit_reachable);
  // abort is never reached: not a failure of the phase.
  EXPECT_TRUE(r.nets[0].ok()) << verify_text(r);
  const Property& p = property(r.nets[1], "no_dead");
  EXPECT_EQ("never fires: recover (bad is never marked)", p.message);
  EXPECT_EQ(1u, r.nets[1].outcomes);  // run.p.complete only
  // Export writes the same nets when told the phases' exits.
  auto c = compile_text(
      "net p { place s = 1; exit complete, abort;\n"
      "  transition go { wait { s } action { TACTIC(EXEC, sleep(1), complete) } } }\n"
      "mission m { place begin = 1, fine, bad; exit closed;\n"
      "  transition run { wait { begin } action { PHASE(p, fine, bad) } }\n"
      "  transition end { wait { fine } signal { closed } }\n"
      "  transition recover { wait { bad } signal { closed } } }");
  ASSERT_TRUE(c->program);
  const std::string narrowed = export_pnml(*c->program, *c->program->find("m"), reachable_phase_exits(r));
  EXPECT_NE(std::string::npos, narrowed.find("run.p.complete"));
  EXPECT_EQ(std::string::npos, narrowed.find("run.p.abort"));
  EXPECT_NE(std::string::npos, export_pnml(*c->program, *c->program->find("m")).find("run.p.abort"));
}

TEST(Verifier, TheMissionOnlyOptionLeavesUnusedPhasesOut) {
  auto c = compile_text(
      "net unused { place s = 1; exit e; transition t { wait { s } signal { s } } }\n"
      "mission m { place begin = 1; exit closed; transition go { wait { begin } signal { closed } } }");
  ASSERT_TRUE(c->program);
  EXPECT_FALSE(verify_program(*c->program).ok());
  VerifyOptions o;
  o.max_states = 1000;
  o.mission_only = true;
  VerifyReport r = verify_program(*c->program, o);
  ASSERT_EQ(1u, r.nets.size());
  EXPECT_TRUE(r.ok());
}

TEST(Verifier, AMissionWithoutExitsEndsWhenNothingIsEnabled) {
  VerifyReport r = verify_text_mission(
      "mission m { place begin = 1, fine;\n"
      "  transition go { wait { begin } action { TACTIC(OOD, shutdown_network, fine) } } }");
  EXPECT_TRUE(r.ok()) << verify_text(r);
  EXPECT_EQ("a mission net without exits ends when nothing is enabled and nothing is in flight",
            property(r.nets[0], "no_deadlock").message);
}

TEST(Verifier, TheStateLimitLeavesWholeGraphPropertiesUndecided) {
  auto c = compile_text(
      "net n { place s = 1, a, b, c, d; exit e;\n"
      "  transition t { wait { s } signal { a, b, c, d } }\n"
      "  transition ta { wait { a } action { TACTIC(EXEC, sleep(1), e) } } }");
  ASSERT_TRUE(c->program);
  VerifyOptions o;
  o.max_states = 2;
  VerifyReport r = verify_program(*c->program, o);
  EXPECT_FALSE(r.nets[0].complete);
  EXPECT_EQ(Status::Undecided, property(r.nets[0], "can_always_end").status);
  EXPECT_FALSE(r.ok());
}

TEST(VerifyReport, JsonHasTheCounterexampleStepsAndTheirText) {
  VerifyReport r = verify_text_mission(
      "net n { place s = 1, ok, stuck; exit e;\n"
      "  transition ask { wait { s } action { TACTIC(ASK, depth_reached, ok, stuck) } }\n"
      "  transition fine { wait { ok } signal { e } } }");
  auto j = verify_json(r);
  EXPECT_FALSE(j["ok"].get<bool>());
  const auto& net = j["nets"][0];
  EXPECT_EQ("n", net["name"]);
  EXPECT_EQ(5u, net["states"].get<std::uint64_t>());
  const auto& deadlock = net["properties"][3];
  EXPECT_EQ("no_deadlock", deadlock["key"]);
  EXPECT_EQ("fails", deadlock["status"]);
  const auto& step = deadlock["counterexample"]["steps"][1];
  EXPECT_EQ("answer", step["kind"]);
  EXPECT_EQ("ask", step["transition"]);
  EXPECT_EQ("ASK depth_reached", step["action"]);
  EXPECT_EQ("0", step["answer"]);
  EXPECT_EQ(nlohmann::ordered_json::array({"stuck"}), step["marks"]);
  EXPECT_EQ("stuck:1", deadlock["counterexample"]["marking"]);
}

std::optional<Program> tank() {
  DiskFileProvider disk;
  core::SourceManager sources;
  core::DiagnosticSink sink;
  return compile_file(std::string(STRATA_SOURCE_DIR) + "/missions/tank/tank.coral", disk, sources, sink);
}

TEST(Verifier, TheTankMissionHoldsEveryPropertyPhasesFirst) {
  auto program = tank();
  ASSERT_TRUE(program);
  VerifyReport r = verify_program(*program);
  EXPECT_TRUE(r.ok()) << verify_text(r);
  std::vector<std::string> order;
  for (const auto& n : r.nets) order.push_back(n.name);
  EXPECT_EQ(
      std::vector<std::string>({"initialize", "dive_from_surface", "submerge_to_depth", "return_to_surface", "tank"}),
      order);
  // Each phase is a state machine: one P-semiflow over all its places, 1.
  for (const auto& n : r.nets) {
    ASSERT_EQ(1u, n.invariants.size()) << n.name;
    EXPECT_EQ(n.bounds.size(), n.invariants[0].weights.size()) << n.name;
    EXPECT_EQ(1u, n.invariants[0].constant) << n.name;
  }
}

TEST(Export, PnmlReadsBackAsTheAnalysisNet) {
  auto program = tank();
  ASSERT_TRUE(program);
  for (const auto& n : program->nets) {
    auto back = petri::parse_pnml(export_pnml(*program, n), n.name + ".pnml");
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(petri::dump_net(build_analysis_net(*program, n).net), petri::dump_net(back.value().net)) << n.name;
    EXPECT_EQ(n.name, back.value().id);
  }
}

TEST(Export, DotShowsActionsInFlightPlacesAndAnswers) {
  auto c = compile_text(
      "net n { place s = 1, a, b; exit e;\n"
      "  transition ask { wait { s } action { TACTIC(ASK, depth_reached, a, b) } }\n"
      "  transition yes { wait { a } signal { e } }\n"
      "  transition no { wait { b*2 } action { TACTIC(REPORT, \"say \\\"no\\\"\") } signal { e } } }");
  ASSERT_TRUE(c->program);
  const std::string dot = export_dot(*c->program, c->program->nets[0]);
  EXPECT_NE(std::string::npos, dot.find("p0 [shape=circle, label=\"s\\n●\"];")) << dot;
  EXPECT_NE(std::string::npos, dot.find("p3 [shape=doublecircle, label=\"e\"];")) << dot;
  EXPECT_NE(std::string::npos, dot.find("label=\"ask\\nASK depth_reached\"")) << dot;
  EXPECT_NE(std::string::npos, dot.find("label=\"no\\nREPORT \\\"say \\\\\\\"no\\\\\\\"\\\"\"")) << dot;
  EXPECT_NE(std::string::npos, dot.find("p4 [shape=circle, style=dashed, label=\"ASK depth_reached\\nin flight\""))
      << dot;
  EXPECT_NE(std::string::npos, dot.find("label=\"answers 0\", tooltip=\"ask.depth_reached.no\"")) << dot;
  EXPECT_NE(std::string::npos, dot.find("p2 -> t2 [label=\"2\"];")) << dot;
}

}  // namespace
}  // namespace strata::coral
