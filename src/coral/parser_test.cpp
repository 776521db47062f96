#include <gtest/gtest.h>

#include "coral/parser.h"

namespace strata::coral {
namespace {

struct Parsed {
  core::SourceManager sources;
  core::DiagnosticSink sink;
  ast::File file;
};

std::unique_ptr<Parsed> parse_text(const std::string& text) {
  auto p = std::make_unique<Parsed>();
  auto id = p->sources.add("x.coral", text);
  p->file = parse(p->sources, id, p->sink);
  return p;
}

TEST(Parser, BuildsTheTreeOfANetWithEveryConstruct) {
  auto p = parse_text(R"(
    import "lib.coral";
    net dive {
      place start = 1, a, b;
      exit complete, abort;
      transition t1 priority 4 {
        wait   { start, a*2 }
        action { TACTIC(EXEC, goto_depth(1.5, -2, "m"), a), TACTIC(REPORT, "hi") }
        signal { b*3 }
      }
      transition t2 { wait { b } action { PHASE(other, complete, abort) } }
    }
    mission m { data "setpoints.toml"; place x = 1; })");
  ASSERT_FALSE(p->sink.has_errors());
  ASSERT_EQ(1u, p->file.imports.size());
  EXPECT_EQ("lib.coral", p->file.imports[0].path);
  ASSERT_EQ(2u, p->file.nets.size());
  const ast::Net& n = p->file.nets[0];
  EXPECT_EQ("dive", n.name.text);
  ASSERT_EQ(5u, n.places.size());
  EXPECT_EQ(1u, n.places[0].initial);
  EXPECT_TRUE(n.places[3].is_exit);
  ASSERT_EQ(2u, n.exits.size());
  const ast::Transition& t1 = n.transitions[0];
  EXPECT_EQ(4, t1.priority);
  ASSERT_EQ(2u, t1.waits.size());
  EXPECT_EQ(2u, t1.waits[1].weight);
  ASSERT_EQ(2u, t1.actions.size());
  const auto& exec = std::get<ast::Tactic>(t1.actions[0]);
  EXPECT_EQ(ast::TacticType::Exec, exec.type);
  EXPECT_EQ("goto_depth", exec.function->name.text);
  ASSERT_EQ(3u, exec.function->args.size());
  EXPECT_EQ(ast::Literal::Kind::Float, exec.function->args[0].kind);
  EXPECT_EQ("-2", exec.function->args[1].text);
  EXPECT_EQ("m", exec.function->args[2].value);
  const auto& report = std::get<ast::Tactic>(t1.actions[1]);
  EXPECT_EQ("hi", report.text->value);
  EXPECT_EQ(3u, t1.signals[0].weight);
  const auto& phase = std::get<ast::Phase>(n.transitions[1].actions[0]);
  EXPECT_EQ("other", phase.phase.text);
  EXPECT_EQ(2u, phase.places.size());
  EXPECT_EQ(ast::Net::Kind::Mission, p->file.nets[1].kind);
  EXPECT_EQ("setpoints.toml", p->file.nets[1].data[0].value);
}

TEST(Parser, NegativePriority) {
  auto p = parse_text("net n { place a = 1; transition t priority -3 { wait { a } } }");
  ASSERT_FALSE(p->sink.has_errors());
  EXPECT_EQ(-3, p->file.nets[0].transitions[0].priority);
}

TEST(Parser, RecoversAndReportsEachMistakeOnce) {
  // Three independent mistakes: a missing ',', a bad clause, a missing ';'.
  auto p = parse_text(
      "net n {\n"
      "  place a = 1, b c;\n"
      "  transition t1 { wait { a } bogus { b } }\n"
      "  transition t2 { wait { b } signal { a } }\n"
      "  place d\n"
      "}\n");
  std::vector<std::uint32_t> lines;
  for (const auto& d : p->sink.diagnostics()) {
    lines.push_back(p->sources.line_col(d.span.file, d.span.offset).line);
    EXPECT_EQ(core::DiagnosticKind::UnexpectedToken, d.kind);
  }
  EXPECT_EQ((std::vector<std::uint32_t>{2, 3, 6}), lines);
  // Recovery kept the later transition.
  ASSERT_EQ(1u, p->file.nets.size());
  EXPECT_EQ(2u, p->file.nets[0].transitions.size());
}

TEST(Parser, WeightZeroIsABadWeight) {
  auto p = parse_text("net n { place a = 1; transition t { wait { a*0 } } }");
  ASSERT_EQ(1u, p->sink.diagnostics().size());
  EXPECT_EQ(core::DiagnosticKind::BadWeight, p->sink.diagnostics()[0].kind);
}

TEST(Parser, UnknownTacticTypeIsNamed) {
  auto p = parse_text("net n { place a = 1; transition t { wait { a } action { TACTIC(RUN, f, a) } } }");
  ASSERT_EQ(1u, p->sink.diagnostics().size());
  EXPECT_EQ(core::DiagnosticKind::UnknownTacticType, p->sink.diagnostics()[0].kind);
}

TEST(Parser, EmptyAndGarbageInputEnd) {
  EXPECT_FALSE(parse_text("")->sink.has_errors());
  EXPECT_TRUE(parse_text("}}}}((((")->sink.has_errors());
  EXPECT_TRUE(parse_text("net")->sink.has_errors());
  EXPECT_TRUE(parse_text("net n { transition")->sink.has_errors());
}

// Regressions: each used to give more than one diagnostic for one mistake.
TEST(Parser, MissingBraceAfterNetNameIsOneError) {
  auto p = parse_text("net foo\n  place a;\n}");
  ASSERT_EQ(1u, p->sink.diagnostics().size());
  ASSERT_EQ(1u, p->file.nets.size());
  EXPECT_EQ(1u, p->file.nets[0].places.size());  // the body was still parsed
}

TEST(Parser, JunkWithBracesInATransitionBodyIsOneError) {
  auto p = parse_text("net n {\n  place a;\n  transition t { foo {x} wait {a} }\n}");
  ASSERT_EQ(1u, p->sink.diagnostics().size());
  ASSERT_EQ(1u, p->file.nets.size());
  EXPECT_EQ(1u, p->file.nets[0].transitions[0].waits.size());
}

TEST(Parser, NegativePriorityOutOfRangeKeepsItsSignInTheMessage) {
  auto p = parse_text("net n { transition t priority -2000000 { } }");
  ASSERT_EQ(1u, p->sink.diagnostics().size());
  EXPECT_EQ("a priority must be from -1000000 to 1000000, not -2000000", p->sink.diagnostics()[0].message);
}

}  // namespace
}  // namespace strata::coral
