#include "coral/edit.h"

#include <gtest/gtest.h>

#include "coral/test_support.h"

namespace strata::coral {
namespace {

using Op = Edit::Op;

const std::string kText =
    "// a comment that stays\n"
    "net n {\n"
    "  place start = 1, middle;  // two places\n"
    "  exit done;\n"
    "\n"
    "  // the first step\n"
    "  transition go {\n"
    "    wait   { start }\n"
    "    action { TACTIC(EXEC, sleep(1), middle) }  // sleep a bit\n"
    "  }\n"
    "  transition end { wait { middle } signal { done } }\n"
    "}\n";

std::string edit(Edit e, const std::string& text = kText) {
  e.net = e.net.empty() ? "n" : e.net;
  auto r = apply_edit(text, e);
  if (!r) return "error: " + r.error().message;
  // Every edit leaves text that compiles.
  auto c = testing::compile_text(r.value());
  EXPECT_TRUE(c->program.has_value()) << r.value();
  return r.value();
}

TEST(Edit, AddPlaceGoesAfterTheLastDeclarationAndKeepsEverythingElse) {
  Edit e;
  e.op = Op::AddPlace;
  e.name = "spare";
  e.value = 2;
  std::string out = edit(e);
  EXPECT_EQ(
      "// a comment that stays\n"
      "net n {\n"
      "  place start = 1, middle;  // two places\n"
      "  exit done;\n"
      "  place spare = 2;\n"
      "\n"
      "  // the first step\n",
      out.substr(0, out.find("  transition go")));
  EXPECT_NE(std::string::npos, out.find("TACTIC(EXEC, sleep(1), middle) }  // sleep a bit"));
}

// Issue 39: a place added after a declaration with a comment at its end
// went between the line and its comment.
TEST(Edit, AddPlaceKeepsTheCommentAtTheEndOfTheLineBeforeIt) {
  Edit e;
  e.op = Op::AddPlace;
  e.name = "spare";
  std::string text = kText;
  text.replace(text.find("  exit done;\n"), 13, "  exit done;  // where it ends\n");
  std::string out = edit(e, text);
  EXPECT_NE(std::string::npos, out.find("  exit done;  // where it ends\n  place spare;\n")) << out;
}

TEST(Edit, AnArcReprintsOnlyItsTransition) {
  Edit e;
  e.op = Op::AddArc;
  e.from = "go";
  e.to = "done";
  e.value = 1;
  std::string out = edit(e);
  EXPECT_NE(std::string::npos, out.find("  transition go {\n"
                                        "    wait   { start }\n"
                                        "    action { TACTIC(EXEC, sleep(1), middle) }\n"
                                        "    signal { done }\n"
                                        "  }\n"))
      << out;
  EXPECT_NE(std::string::npos, out.find("  transition end { wait { middle } signal { done } }\n"));
  EXPECT_NE(std::string::npos, out.find("// the first step"));
  Edit w;
  w.op = Op::SetWeight;
  w.from = "middle";
  w.to = "end";
  w.value = 3;
  EXPECT_NE(std::string::npos, edit(w).find("wait   { middle*3 }"));
  Edit bad;
  bad.op = Op::AddArc;
  bad.from = "start";
  bad.to = "middle";
  EXPECT_EQ("error: an arc joins a place and a transition of net 'n'; 'start' -> 'middle' does not", edit(bad));
}

TEST(Edit, RenameTouchesOnlyTheNames) {
  Edit e;
  e.op = Op::RenamePlace;
  e.name = "middle";
  e.to = "halfway";
  // A comment, a string and a longer name holding the old one stay as they are.
  std::string text = "// the middle of it\n" + kText.substr(0, kText.size() - 2) +
                     "  transition r { wait { middle_x } action { TACTIC(REPORT, \"middle\") } }\n}\n";
  text.replace(text.find("  exit done;\n"), 0, "  place middle_x;\n");
  std::string out = edit(e, text);
  EXPECT_NE(std::string::npos, out.find("place start = 1, halfway;  // two places"));
  EXPECT_NE(std::string::npos, out.find("TACTIC(EXEC, sleep(1), halfway) }  // sleep a bit"));
  EXPECT_NE(std::string::npos, out.find("transition end { wait { halfway } signal { done } }"));
  // Only: the text with exactly those three uses replaced, nothing else.
  std::string expected = text;
  for (const char* use : {"1, middle;", "sleep(1), middle)", "wait { middle }"}) {
    const std::string was(use);
    std::string now = was;
    now.replace(now.find("middle"), 6, "halfway");
    ASSERT_NE(std::string::npos, expected.find(was)) << was;
    expected.replace(expected.find(was), was.size(), now);
  }
  EXPECT_EQ(expected, out);
  Edit taken = e;
  taken.to = "start";
  EXPECT_EQ("error: 'start' is already used in net 'n'", edit(taken));
  Edit keyword = e;
  keyword.to = "wait";
  EXPECT_EQ("error: 'wait' is not a name (letters, digits and '_', not a keyword)", edit(keyword));
}

TEST(Edit, DeleteAPlaceFromAListAndItsArcs) {
  Edit e;
  e.op = Op::DeletePlace;
  e.name = "middle";
  auto r = apply_edit(kText, Edit{Op::DeletePlace, "n", "middle", "", "", 0, {}});
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_NE(std::string::npos, r.value().find("  place start = 1;  // two places\n")) << r.value();
  EXPECT_NE(std::string::npos, r.value().find("  transition end {\n    signal { done }\n  }\n")) << r.value();
}

TEST(Edit, AddAndDeleteTransitions) {
  Edit add;
  add.op = Op::AddTransition;
  add.name = "later";
  std::string out = edit(add);
  EXPECT_NE(std::string::npos, out.find("signal { done } }\n  transition later { }\n}\n")) << out;
  Edit del;
  del.op = Op::DeleteTransition;
  del.name = "end";
  out = edit(del);
  EXPECT_EQ(std::string::npos, out.find("transition end"));
  EXPECT_NE(std::string::npos, out.find("  }\n}\n")) << out;
}

TEST(Edit, SetInitialAndActions) {
  Edit e;
  e.op = Op::SetInitial;
  e.name = "middle";
  e.value = 4;
  EXPECT_NE(std::string::npos, edit(e).find("place start = 1, middle = 4;"));
  e.name = "start";
  e.value = 0;
  EXPECT_NE(std::string::npos, edit(e).find("place start = 0, middle;"));
  Edit a;
  a.op = Op::SetActions;
  a.name = "go";
  a.actions = {"TACTIC(REPORT, \"off we go\")", "TACTIC(ASK, depth_reached, middle, start)"};
  std::string out = edit(a);
  EXPECT_NE(std::string::npos, out.find("    action { TACTIC(REPORT, \"off we go\"),\n"
                                        "             TACTIC(ASK, depth_reached, middle, start) }\n"))
      << out;
}

TEST(Edit, UnknownNetOrNode) {
  EXPECT_EQ("error: no net 'zz' in the text", edit(Edit{Op::AddPlace, "zz", "p", "", "", 0, {}}));
  EXPECT_EQ("error: no transition 'nope' in net 'n'", edit(Edit{Op::DeleteTransition, "n", "nope", "", "", 0, {}}));
}

}  // namespace
}  // namespace strata::coral
