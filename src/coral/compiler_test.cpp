#include <filesystem>
#include <set>

#include <gtest/gtest.h>

#include "coral/test_support.h"
#include "petri/dump.h"
#include "petri/state.h"

namespace strata::coral {
namespace {

using testing::compile_text;

TEST(Compiler, WaitIsPreSignalIsPostActionsAreATable) {
  auto c = compile_text(
      "net n { place s = 2, a, b; exit e;\n"
      "  transition t1 priority 1 { wait { s*2 } action { TACTIC(ASK, q, a, b) } signal { e } }\n"
      "  transition t2 { wait { a } action { TACTIC(EXEC, sleep(1), e) } }\n"
      "  transition t3 { wait { b } signal { e*2 } } }");
  ASSERT_TRUE(c->program);
  const CompiledNet& n = c->program->nets[0];
  EXPECT_EQ(
      "net n\n"
      "exits [e]\n"
      "place s = 2\nplace a = 0\nplace b = 0\nplace e = 0\n"
      "transition t1 priority 1: in{s*2} out{e}\n"
      "transition t2: in{a} out{}\n"
      "transition t3: in{b} out{e*2}\n"
      "action t1: TACTIC(ASK, q) -> [a, b]\n"
      "action t2: TACTIC(EXEC, sleep(1)) -> [e]\n",
      dump_net(n));
  // The compiled net fires like the text says.
  petri::State s(n.net);
  EXPECT_EQ(0u, s.enabled().first());
  ASSERT_TRUE(s.fire(0).ok());
  EXPECT_EQ("e:1", petri::dump_marking(n.net, s.marking()));
}

// Regression: REPORT text and the data path were dumped unescaped, so a
// newline in a report broke the one-line-per-action dump.
TEST(Compiler, DumpEscapesReportTextAndDataPath) {
  auto c = compile_text(
      "mission m { data \"a \\\"b\\\".toml\"; place s = 1; exit e;\n"
      "  transition t { wait { s } action { TACTIC(REPORT, \"say \\\"hi\\\"\\n\\tnext\") } signal { e } } }");
  ASSERT_TRUE(c->program) << ::testing::PrintToString(c->kinds());
  std::string dump = dump_net(c->program->nets[0]);
  EXPECT_NE(std::string::npos, dump.find("data \"a \\\"b\\\".toml\"\n")) << dump;
  EXPECT_NE(std::string::npos, dump.find("action t: TACTIC(REPORT, \"say \\\"hi\\\"\\n\\tnext\") -> []\n")) << dump;
}

TEST(Compiler, DataFileResolvesAgainstTheMissionFolder) {
  auto c = compile_text("import \"sub/m.coral\";", {{"sub/m.coral",
                                                     "mission m { data \"sp.toml\"; place s = 1; exit e;\n"
                                                     "transition t { wait { s } signal { e } } }"}});
  ASSERT_TRUE(c->program);
  ASSERT_TRUE(c->program->mission);
  EXPECT_EQ("sub/sp.toml", c->program->nets[*c->program->mission].data_file);
}

// The paper's mission, as shipped: five nets, each phase with the exits
// complete and abort, the global net sequencing them.
TEST(Compiler, TankMissionCompiles) {
  std::string root = std::string(STRATA_SOURCE_DIR) + "/missions/tank/tank.coral";
  DiskFileProvider disk;
  core::SourceManager sources;
  core::DiagnosticSink sink;
  auto program = compile_file(root, disk, sources, sink);
  ASSERT_TRUE(program);
  EXPECT_EQ(0u, sink.warning_count());
  ASSERT_TRUE(program->mission);
  EXPECT_EQ("tank", program->nets[*program->mission].name);
  for (const char* phase : {"initialize", "dive_from_surface", "submerge_to_depth", "return_to_surface"}) {
    const CompiledNet* n = program->find(phase);
    ASSERT_TRUE(n) << phase;
    ASSERT_EQ(2u, n->exits.size());
    EXPECT_EQ("complete", n->net.place_name(n->exits[0]));
    EXPECT_EQ("abort", n->net.place_name(n->exits[1]));
  }
  // Phase 2 uses Figure 10's primitives.
  std::set<std::string> prims;
  for (const auto& acts : program->find("dive_from_surface")->actions) {
    for (const auto& a : acts) prims.insert(a.target);
  }
  EXPECT_EQ((std::set<std::string>{"next_setpt_data", "depth_filter_off", "start_depth_filter", "sleep", "submerge",
                                   "start_timer", "depth_reached", "time_out", "system_problem", "surface",
                                   "surface_reached"}),
            prims);
}

}  // namespace
}  // namespace strata::coral
