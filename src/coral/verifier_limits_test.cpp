// The verifier at its limits (states, memory, time, nesting, semiflows),
// its warnings and dead transitions, the tank mission, the JSON report and
// the exports. The properties one by one are verifier_test.cpp.
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
