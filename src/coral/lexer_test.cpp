#include <gtest/gtest.h>

#include "coral/lexer.h"

namespace strata::coral {
namespace {

std::vector<std::string> lex(std::string_view text, core::DiagnosticSink& sink) {
  Lexer lexer(0, text, sink);
  std::vector<std::string> out;
  for (Token t = lexer.next(); t.kind != TokenKind::EndOfFile; t = lexer.next()) {
    out.push_back(std::string(token_kind_name(t.kind)) + "(" + std::string(t.text) + ")");
  }
  return out;
}

TEST(Lexer, KeywordsNamesNumbersStringsAndPunctuation) {
  core::DiagnosticSink sink;
  auto toks = lex("transition t priority -2 { wait { a*2 } action { TACTIC(EXEC, f(1.5, \"x\\\"y\"), p) } }", sink);
  std::vector<std::string> want = {"transition(transition)",
                                   "a name(t)",
                                   "priority(priority)",
                                   "an integer(-2)",
                                   "'{'({)",
                                   "wait(wait)",
                                   "'{'({)",
                                   "a name(a)",
                                   "'*'(*)",
                                   "an integer(2)",
                                   "'}'(})",
                                   "action(action)",
                                   "'{'({)",
                                   "TACTIC(TACTIC)",
                                   "'('(()",
                                   "a name(EXEC)",
                                   "','(,)",
                                   "a name(f)",
                                   "'('(()",
                                   "a number(1.5)",
                                   "','(,)",
                                   "a string(\"x\\\"y\")",
                                   "')'())",
                                   "','(,)",
                                   "a name(p)",
                                   "')'())",
                                   "'}'(})",
                                   "'}'(})"};
  EXPECT_EQ(want, toks);
  EXPECT_FALSE(sink.has_errors());
}

TEST(Lexer, CommentsAreSkipped) {
  core::DiagnosticSink sink;
  EXPECT_EQ((std::vector<std::string>{"a name(a)", "a name(b)"}),
            lex("// line\na /* block\n * more */ b // end", sink));
  EXPECT_FALSE(sink.has_errors());
}

TEST(Lexer, UnterminatedCommentAndStringAreReported) {
  core::DiagnosticSink sink;
  lex("a \"open\nb /* never closed", sink);
  ASSERT_EQ(2u, sink.diagnostics().size());
  EXPECT_EQ(core::DiagnosticKind::UnterminatedString, sink.diagnostics()[0].kind);
  EXPECT_EQ(core::DiagnosticKind::UnterminatedComment, sink.diagnostics()[1].kind);
}

TEST(Lexer, RunOfBadBytesIsOneDiagnostic) {
  core::DiagnosticSink sink;
  auto toks = lex("a \x01\x02\x03\xff b", sink);
  EXPECT_EQ((std::vector<std::string>{"a name(a)", "a name(b)"}), toks);
  ASSERT_EQ(1u, sink.diagnostics().size());
  EXPECT_EQ(core::DiagnosticKind::InvalidCharacter, sink.diagnostics()[0].kind);
}

TEST(Lexer, MalformedNumberAndLongToken) {
  core::DiagnosticSink sink;
  lex("12ab " + std::string(kMaxTokenLength + 1, 'x'), sink);
  ASSERT_EQ(2u, sink.diagnostics().size());
  EXPECT_EQ(core::DiagnosticKind::InvalidNumber, sink.diagnostics()[0].kind);
  EXPECT_EQ(core::DiagnosticKind::TokenTooLong, sink.diagnostics()[1].kind);
}

TEST(Lexer, BackslashAtTheEndOfALineIsOnlyAnUnterminatedString) {
  core::DiagnosticSink sink;
  lex("\"abc\\\nnext", sink);
  ASSERT_EQ(1u, sink.diagnostics().size());
  EXPECT_EQ(core::DiagnosticKind::UnterminatedString, sink.diagnostics()[0].kind);
}

TEST(Lexer, EscapeIsTheInverseOfUnescape) {
  for (std::string s : {"", "plain", "say \"hi\"\n\tnext", "back\\slash"}) {
    EXPECT_EQ(s, unescape(escape(s)));
  }
  EXPECT_EQ("\"a\\nb\"", escape("a\nb"));
}

TEST(Lexer, UnescapeAppliesEscapes) { EXPECT_EQ("a\"b\\c\nd\te", unescape("\"a\\\"b\\\\c\\nd\\te\"")); }

}  // namespace
}  // namespace strata::coral
