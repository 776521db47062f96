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
