#include <gtest/gtest.h>

#include "coral/test_support.h"

namespace strata::coral {
namespace {

using testing::compile_text;

TEST(Checker, UndefinedPlaceSuggestsTheClosestName) {
  auto c = compile_text(
      "net n { place start = 1; exit done;\n"
      "  transition t { wait { strat } signal { done } } }");
  ASSERT_EQ((std::vector<std::string>{"2:25 UndefinedPlace"}), c->kinds());
  ASSERT_EQ(1u, c->sink.diagnostics()[0].notes.size());
  EXPECT_EQ("did you mean 'start'?", c->sink.diagnostics()[0].notes[0].message);
}

TEST(Checker, TacticPlaceCountsFollowTheType) {
  auto c = compile_text(
      "net n { place s = 1, a, b; exit e;\n"
      "  transition t1 { wait { s } action { TACTIC(ASK, q, a) } }\n"
      "  transition t2 { wait { a } action { TACTIC(EXEC, f, a, b) } }\n"
      "  transition t3 { wait { b } action { TACTIC(REPORT, \"x\", b) } }\n"
      "  transition t4 { wait { b } action { TACTIC(OOD, f) } signal { e } } }");
  EXPECT_EQ((std::vector<std::string>{"2:46 TacticArity", "3:46 TacticArity", "4:46 TacticArity", "5:46 TacticArity"}),
            c->kinds());
}

TEST(Checker, PhaseNeedsOnePlacePerExit) {
  auto c = compile_text(
      "net ph { place s = 1; exit ok, bad; transition t { wait { s } signal { ok } }\n"
      "  transition u { wait { s } signal { bad } } }\n"
      "mission m { place b = 1, x; transition go { wait { b } action { PHASE(ph, x) } }\n"
      "  transition stop { wait { x } } }");
  ASSERT_EQ((std::vector<std::string>{"3:71 PhaseArity"}), c->kinds());
  EXPECT_EQ("its exits, in order: ok, bad", c->sink.diagnostics()[0].notes[0].message);
}

TEST(Checker, UnknownPhaseAndPhaseRecursion) {
  auto c = compile_text(
      "net a { place s = 1; exit e; transition t { wait { s } action { PHASE(b, e) } } }\n"
      "net b { place s = 1; exit e; transition t { wait { s } action { PHASE(a, e) } } }\n"
      "net c { place s = 1; exit e; transition t { wait { s } action { PHASE(zz, e) } } }\n");
  EXPECT_EQ((std::vector<std::string>{"2:71 PhaseRecursion", "3:71 UnknownPhase"}), c->kinds());
}

TEST(Checker, DuplicatesAcrossTheLibrary) {
  auto c =
      compile_text("import \"x.coral\";\nnet n { place a = 1, a; exit e; transition t { wait { a } signal { e } } }",
                   {{"x.coral", "net n { place s = 1; exit e; transition t { wait { s } signal { e } } }"}});
  auto kinds = c->kinds();
  EXPECT_EQ((std::vector<std::string>{"2:22 DuplicatePlace", "1:5 DuplicateNet"}), kinds);
}

TEST(Checker, StructuralWarnings) {
  auto c = compile_text(
      "net n { place s = 1, lonely, never; exit e, unreached;\n"
      "  transition go { wait { s } signal { e } }\n"
      "  transition dead { wait { never } signal { e } }\n"
      "  transition spin { signal { s } } }");
  EXPECT_TRUE(c->program);  // warnings do not stop compilation
  EXPECT_EQ((std::vector<std::string>{"1:22 UnusedPlace", "1:45 ExitNeverMarked", "3:14 NeverEnabled", "4:14 NoInput"}),
            c->kinds());
}

TEST(Checker, NeverEnabledFollowsChainsOfDeadTransitions) {
  auto c = compile_text(
      "net n { place s = 1, a, b; exit e;\n"
      "  transition go { wait { s } signal { e } }\n"
      "  transition t1 { wait { a } signal { b } }\n"
      "  transition t2 { wait { b } signal { a } } }");
  EXPECT_EQ((std::vector<std::string>{"3:14 NeverEnabled", "4:14 NeverEnabled"}), c->kinds());
}

// Regression: the fixpoint was a pass per link on nets declared against the
// flow; the worklist must still reach every transition.
TEST(Checker, ChainDeclaredAgainstTheFlowIsLive) {
  std::string text = "net n { place p0 = 1";
  for (int i = 1; i <= 50; ++i) text += ", p" + std::to_string(i);
  text += "; exit e;\n";
  for (int i = 50; i >= 1; --i) {
    text += "transition t" + std::to_string(i) + " { wait { p" + std::to_string(i - 1) + " } signal { p" +
            std::to_string(i) + " } }\n";
  }
  text += "transition last { wait { p50 } signal { e } } }";
  auto c = compile_text(text);
  EXPECT_TRUE(c->program);
  EXPECT_TRUE(c->kinds().empty()) << ::testing::PrintToString(c->kinds());
}

TEST(Checker, PrimitivesAreCheckedAgainstTheCatalogueWhenGiven) {
  CheckOptions options;
  options.primitive = [](std::string_view name) -> std::optional<PrimitiveSignature> {
    if (name == "depth_reached") return PrimitiveSignature{ast::TacticType::Ask, 0, 0, {}};
    if (name == "sleep") return PrimitiveSignature{ast::TacticType::Exec, 1, 1, {}};
    return std::nullopt;
  };
  options.primitive_names = {"depth_reached", "sleep"};
  auto c = compile_text(
      "net n { place s = 1, a, b; exit e;\n"
      "  transition t1 { wait { s } action { TACTIC(ASK, depth_reachd, a, b) } }\n"
      "  transition t2 { wait { a } action { TACTIC(EXEC, sleep, e) } }\n"
      "  transition t3 { wait { b } action { TACTIC(EXEC, depth_reached, e) } } }",
      {}, options);
  EXPECT_EQ((std::vector<std::string>{"2:51 UnknownPrimitive", "3:52 PrimitiveArity", "4:52 TacticArguments"}),
            c->kinds());
  EXPECT_EQ("did you mean 'depth_reached'?", c->sink.diagnostics()[0].notes[0].message);
}

TEST(Checker, APrimitiveTheVehicleCannotCarryOutIsRefusedAtEachCallInEveryNet) {
  CheckOptions options;
  options.primitive = [](std::string_view name) -> std::optional<PrimitiveSignature> {
    if (name == "sleep") return PrimitiveSignature{ast::TacticType::Exec, 1, 1, {}};
    if (name == "start_sonar") {
      PrimitiveSignature sig{ast::TacticType::Exec, 0, 0, {}};
      sig.unavailable = "it has no sonar";
      return sig;
    }
    return std::nullopt;
  };
  options.execution_level = "a test vehicle";
  auto c = compile_text(
      "import \"lib.coral\";\n"
      "mission m { place s = 1, a; exit e;\n"
      "  transition t1 { wait { s } action { TACTIC(EXEC, start_sonar, a) } }\n"
      "  transition t2 { wait { a } action { TACTIC(EXEC, sleep(1), e) } } }",
      {{"lib.coral",
        "net scan { place s = 1; exit e;\n"
        "  transition t { wait { s } action { TACTIC(EXEC, start_sonar, e) } } }"}},
      options);
  EXPECT_FALSE(c->program);
  ASSERT_EQ((std::vector<std::string>{"3:52 PrimitiveUnavailable", "2:51 PrimitiveUnavailable"}), c->kinds());
  EXPECT_EQ("'start_sonar' is not available on a test vehicle: it has no sonar", c->sink.diagnostics()[0].message);
  EXPECT_EQ("lib.coral", c->sources.path(c->sink.diagnostics()[1].span.file));
}

TEST(Checker, OneMissionPerLoadAndDataOnlyInMissions) {
  auto c = compile_text(
      "mission a { place s = 1; transition t { wait { s } } }\n"
      "mission b { place s = 1; transition t { wait { s } } }\n"
      "net p { data \"x.toml\"; place s = 1; transition t { wait { s } } }");
  EXPECT_EQ((std::vector<std::string>{"2:9 MultipleMissions", "3:14 DataOutsideMission"}), c->kinds());
}

TEST(Checker, MissionCalledAsAPhaseIsReportedOnce) {
  auto c = compile_text("mission m { place a = 1; transition t { wait {a} action {PHASE(m)} } }");
  EXPECT_EQ((std::vector<std::string>{"1:64 PhaseIsMission"}), c->kinds());
}

// Regression: past the error limit the sink stopped counting, so a later
// net with an undeclared place was thought clean and its structural
// warnings threw on the unknown name: exit 70 instead of 65.
TEST(Checker, ErrorsPastTheLimitDoNotReachTheWarnings) {
  std::string text = "net a { place p;\n";
  for (int i = 0; i < 60; ++i)
    text += "transition t" + std::to_string(i) + " { wait { q" + std::to_string(i) + " } }\n";
  text += "}\nnet b { place x; transition u { wait { nope } } }\n";
  std::unique_ptr<testing::Compiled> c;
  ASSERT_NO_THROW(c = compile_text(text));
  EXPECT_FALSE(c->program);
  EXPECT_TRUE(c->sink.saturated());
}

}  // namespace
}  // namespace strata::coral
