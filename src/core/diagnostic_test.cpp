#include <set>
#include <sstream>

#include <gtest/gtest.h>

#include "core/diagnostic.h"
#include "core/diagnostic_printer.h"

namespace strata::core {
namespace {

TEST(SourceManager, LineAndColumnAreOneBased) {
  SourceManager sm;
  FileId f = sm.add("a.coral", "ab\ncd\r\nef");
  EXPECT_EQ(1u, sm.line_col(f, 0).line);
  EXPECT_EQ(1u, sm.line_col(f, 0).col);
  EXPECT_EQ(2u, sm.line_col(f, 4).line);
  EXPECT_EQ(2u, sm.line_col(f, 4).col);
  EXPECT_EQ("cd", sm.line_text(f, 2));  // no \r
  EXPECT_EQ("ef", sm.line_text(f, 3));
  EXPECT_EQ("", sm.line_text(f, 9));
}

TEST(DiagnosticPrinter, ShowsLineCaretKindAndNotes) {
  SourceManager sm;
  std::string text = "net n {\n  action { TACTIC(ASK, depth_reachd, a, b) }\n}\n";
  FileId f = sm.add("tank.coral", text);
  auto at = static_cast<std::uint32_t>(text.find("depth_reachd"));
  DiagnosticSink sink;
  auto* d = sink.report(DiagnosticKind::UnknownPrimitive, {f, at, 12}, "unknown primitive 'depth_reachd'");
  add_note(d, {f, at, 12}, "did you mean 'depth_reached'?");
  std::ostringstream out;
  print_diagnostics(out, sm, sink.diagnostics());
  EXPECT_EQ(
      "tank.coral:2:24: error: unknown primitive 'depth_reachd' [UnknownPrimitive]\n"
      "     action { TACTIC(ASK, depth_reachd, a, b) }\n"
      "                          ^~~~~~~~~~~~\n"
      "tank.coral:2:24: note: did you mean 'depth_reached'?\n"
      "     action { TACTIC(ASK, depth_reachd, a, b) }\n"
      "                          ^~~~~~~~~~~~\n",
      out.str());
}

TEST(DiagnosticPrinter, ProblemWithoutFileHasNoLocation) {
  SourceManager sm;
  DiagnosticSink sink;
  sink.report(DiagnosticKind::FileUnreadable, {FileId(-1), 0, 0}, "cannot open 'x'");
  std::ostringstream out;
  print_diagnostics(out, sm, sink.diagnostics());
  EXPECT_EQ("strata: error: cannot open 'x' [FileUnreadable]\n", out.str());
}

TEST(SourceManager, OffsetOfALineAndColumnIsClampedToTheText) {
  SourceManager sm;
  FileId f = sm.add("m.pl", "ab\ncd\r\nef");
  EXPECT_EQ(0u, sm.offset_of(f, {1, 1}));
  EXPECT_EQ(4u, sm.offset_of(f, {2, 2}));
  EXPECT_EQ(5u, sm.offset_of(f, {2, 9}));   // past the line: its end (before \r\n)
  EXPECT_EQ(7u, sm.offset_of(f, {3, 0}));   // no column: the line's start
  EXPECT_EQ(9u, sm.offset_of(f, {8, 99}));  // past the last line: the last line's end
}

// A tool outside Strata (SWI-Prolog) may give a line without a column, or a
// file alone: the printers show no more than is known.
TEST(DiagnosticPrinter, ALineWithoutColumnHasNoColumnAndNoCaret) {
  SourceManager sm;
  FileId f = sm.add("m.pl", "p(X) :- true.\nmission.\n");
  DiagnosticSink sink;
  sink.report(DiagnosticKind::PrologLoadWarning, {f, sm.offset_of(f, {1, 1}), 0}, "Singleton variables: [X]")
      ->precision = Precision::Line;
  sink.report(DiagnosticKind::PrologLoadError, {f, 0, 0}, "loading took too long")->precision = Precision::File;
  std::ostringstream out;
  print_diagnostics(out, sm, sink.diagnostics());
  EXPECT_EQ(
      "m.pl:1: warning: Singleton variables: [X] [PrologLoadWarning]\n"
      "   p(X) :- true.\n"
      "m.pl: error: loading took too long [PrologLoadError]\n",
      out.str());
  auto j = diagnostics_to_json(sm, sink.diagnostics());
  EXPECT_EQ(R"({"file":"m.pl","kind":"PrologLoadWarning","line":1,"message":"Singleton variables: [X]","notes":[],)"
            R"("severity":"warning"})",
            j[0].dump());
  EXPECT_EQ(
      R"({"file":"m.pl","kind":"PrologLoadError","message":"loading took too long","notes":[],"severity":"error"})",
      j[1].dump());
}

TEST(DiagnosticJson, APlaceHasFileLineColAndItsEnd) {
  SourceManager sm;
  FileId f = sm.add("x.coral", "net n { place a b; }\n");
  DiagnosticSink sink;
  sink.report(DiagnosticKind::UnexpectedToken, {f, 16, 1}, "expected ';'");
  EXPECT_EQ(R"({"col":17,"end_col":18,"end_line":1,"file":"x.coral","kind":"UnexpectedToken","line":1,)"
            R"("message":"expected ';'","notes":[],"severity":"error"})",
            diagnostics_to_json(sm, sink.diagnostics())[0].dump());
}

TEST(DiagnosticJson, InvalidUtf8InMessagesIsReplacedNotThrown) {
  SourceManager sm;
  FileId f = sm.add("x.coral", "\xff\xfe");
  DiagnosticSink sink;
  sink.report(DiagnosticKind::InvalidCharacter, {f, 0, 2}, "unexpected \xff");
  auto j = diagnostics_to_json(sm, sink.diagnostics());
  std::string text;
  ASSERT_NO_THROW(text = dump_json(j));
  EXPECT_NE(std::string::npos, text.find("\"kind\": \"InvalidCharacter\""));
  EXPECT_EQ(1, j[0]["line"]);
  EXPECT_EQ(1, j[0]["col"]);
}

TEST(DiagnosticSink, StopsAtTheErrorLimitWithOneTooManyErrors) {
  DiagnosticSink sink(3);
  for (int i = 0; i < 10; ++i) sink.report(DiagnosticKind::UnexpectedToken, {}, "x");
  ASSERT_EQ(4u, sink.diagnostics().size());
  EXPECT_EQ(DiagnosticKind::TooManyErrors, sink.diagnostics().back().kind);
  EXPECT_TRUE(sink.saturated());
}

TEST(DiagnosticKinds, NamesAreUniqueAndDescribed) {
  std::set<std::string_view> names;
  for (auto k : all_kinds()) {
    EXPECT_TRUE(names.insert(kind_name(k)).second) << kind_name(k);
    EXPECT_FALSE(kind_description(k).empty());
  }
  EXPECT_EQ(Severity::Warning, default_severity(DiagnosticKind::NoInput));
}

}  // namespace
}  // namespace strata::core
