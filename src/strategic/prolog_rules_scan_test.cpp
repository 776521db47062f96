// The scan before SWI-Prolog's reader (prolog_rules_scan.h) on what a
// careless or hostile rule file holds: each refusal at its place, and text
// that ends inside a quote, a comment or an escape never read past its end.
#include "strategic/prolog_rules_scan.h"

#include <string>

#include <gtest/gtest.h>

namespace strata::strategic {
namespace {

std::string where(std::string_view text) {
  const auto p = scan_rules_text(text);
  return p ? std::to_string(p->line) + ":" + std::to_string(p->column) : "ok";
}

TEST(RulesScan, ADigitBeforeAQuoteIsRefusedAtTheDigit) {
  EXPECT_EQ("2:6", where("m.\np :- 0'a."));
  EXPECT_EQ("1:11", where("p :- X = 16'FF."));  // the digit before the quote
  EXPECT_EQ("1:6", where("p :- 9'"));           // at the very end of the file
  const auto p = scan_rules_text("p :- 0'a.");
  ASSERT_TRUE(p);
  EXPECT_NE(std::string::npos, p->text.find("a digit followed by a quote")) << p->text;
}

TEST(RulesScan, QuotedTextAndCommentsAreSkipped) {
  EXPECT_EQ("ok", where("% 10's\n/* 0'a || =/* */\np :- A = 'it''s 3', B = \"10'\", C = `0'`.\n"));
  EXPECT_EQ("ok", where("p :- X = a1, Y = 'q'."));  // a quote after a word's digit is refused below
  EXPECT_EQ("1:11", where("p :- X = a1'q'."));
}

TEST(RulesScan, LinesCountedThroughQuotesCommentsAndContinuations) {
  EXPECT_EQ("5:5", where("p :- X = 'a\\\nb\nc',\n/* x\n */ 0'a."));
}

TEST(RulesScan, QuasiQuotationAndCommentGluedToASymbolAreRefused) {
  EXPECT_EQ("1:13", where("p :- X = {|x||y|}."));
  EXPECT_EQ("1:9", where("p :- X =/* c */ 1."));
  EXPECT_EQ("ok", where("p :- X = /* c */ 1, Y = (a | b)."));
}

TEST(RulesScan, TextEndingInsideAQuoteACommentOrAnEscapeIsFine) {
  for (const char* text : {"p :- X = 'never closed", "p :- X = \"ends in \\", "/* never closed", "/* ends in *",
                           "p :- X = '\\", "'", "\\", "/", "%", ""}) {
    EXPECT_EQ("ok", where(text)) << text;
  }
}

TEST(RulesScan, DeepNestingAndLongLinesAreRefused) {
  EXPECT_EQ("ok", where("p(" + std::string(999, '(') + std::string(999, ')') + ")."));
  EXPECT_EQ("1:1001", where(std::string(1001, '[')));
  EXPECT_EQ("2:1", where("p.\n" + std::string(100'001, 'a')));
  EXPECT_EQ("ok", where(std::string(5000, ')')));  // closing more than opened is the reader's to say
}

}  // namespace
}  // namespace strata::strategic
