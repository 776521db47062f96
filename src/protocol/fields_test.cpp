#include "protocol/fields.h"

#include <cmath>
#include <limits>
#include <string>

#include <fmt/format.h>

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

namespace strata::protocol {
namespace {

// Fields as one string: bare ones as they are, quoted ones in <...>.
std::string show(const SplitResult& s) {
  std::string out;
  for (const Field& f : s.fields) {
    if (!out.empty()) out += ' ';
    out += f.quoted ? "<" + f.text + ">" : f.text;
  }
  if (!s.ok()) out += " !" + s.error;
  return out;
}

TEST(Fields, SplitsOnRunsOfSpaces) {
  EXPECT_EQ("exec 8 setpoint 0.6 30", show(split_fields("  exec 8  setpoint 0.6   30 ")));
  EXPECT_EQ("tlm 1.5 depth=2.0", show(split_fields("tlm 1.5 depth=2.0")));
}

TEST(Fields, QuotedStringsApplyTheFourEscapes) {
  SplitResult s = split_fields(R"(event 3.0 "a \"b\" \\ c\nd\te" x)");
  ASSERT_TRUE(s.ok()) << s.error;
  ASSERT_EQ(4u, s.fields.size());
  EXPECT_TRUE(s.fields[2].quoted);
  EXPECT_EQ("a \"b\" \\ c\nd\te", s.fields[2].text);
  EXPECT_EQ(11u, s.fields[2].column);
  EXPECT_EQ("<>", show(split_fields(R"("")")));
}

TEST(Fields, RejectsWhatTheGrammarDoesNot) {
  EXPECT_EQ(" !empty line", show(split_fields("")));
  EXPECT_EQ(" !empty line", show(split_fields("    ")));
  EXPECT_EQ("exec 4 !bad escape '\\q' at column 10 (only \\\" \\\\ \\n \\t)", show(split_fields(R"(exec 4 "a\qb")")));
  EXPECT_EQ("exec !unterminated quoted string starting at column 6", show(split_fields(R"(exec "abc)")));
  EXPECT_EQ("exec !unterminated quoted string starting at column 6", show(split_fields(R"(exec "abc\)")));
  EXPECT_EQ("exec !a quoted string must be followed by a space (column 11)", show(split_fields(R"(exec "abc"d)")));
  EXPECT_EQ("exec !character '\"' at column 8 is not allowed outside quotes", show(split_fields(R"(exec ab"c")")));
  EXPECT_EQ("x !character '#' at column 3 is not allowed outside quotes", show(split_fields("x #1")));
  EXPECT_EQ(" !byte 0x09 at column 2 is not printable ASCII", show(split_fields("x\ty")));
  EXPECT_EQ("x !byte 0xc3 at column 4 is not printable ASCII", show(split_fields("x \"\xc3\xa9\"")));
  EXPECT_EQ("x !byte 0x0d at column 4 is not printable ASCII", show(split_fields("x y\r")));
  EXPECT_EQ("x !byte 0x00 at column 5 is not printable ASCII", show(split_fields(std::string_view("x \"\\\0\"", 6))));
}

TEST(Fields, AtMostMaxFields) {
  std::string line = "exec 1 f";
  for (std::size_t i = 3; i < kMaxFields; ++i) line += " 1";
  EXPECT_TRUE(split_fields(line).ok());
  SplitResult s = split_fields(line + " 1");
  EXPECT_EQ(fmt::format("more than {} fields", kMaxFields), s.error);
  EXPECT_EQ(kMaxFields, s.fields.size());
}

TEST(Fields, QuoteEscapesAndReplacesWhatCannotBeCarried) {
  EXPECT_EQ(R"("a \"b\" \\ \n\t")", quote("a \"b\" \\ \n\t"));
  EXPECT_EQ(R"("x?y?")", quote("x\ry\xff"));
  EXPECT_EQ("sleep", bare_or_quoted("sleep"));
  EXPECT_EQ(R"("two words")", bare_or_quoted("two words"));
  EXPECT_EQ(R"("")", bare_or_quoted(""));
}

TEST(Fields, QuoteWithinCutsAndMarksTheCut) {
  EXPECT_EQ(R"("abcdef")", quote_within("abcdef", 8));
  EXPECT_EQ(R"("ab...")", quote_within("abcdefg", 7));
  // An escape is never split.
  EXPECT_EQ(R"("a...")", quote_within("a\"bcdefg", 7));
  EXPECT_EQ(R"("...")", quote_within("abcdefg", 5));
}

TEST(Fields, DoublesAlwaysReadBackAsFloats) {
  EXPECT_EQ("1.0", format_double(1.0));
  EXPECT_EQ("-0.0", format_double(-0.0));
  EXPECT_EQ("0.6", format_double(0.6));
  EXPECT_EQ("1e+20", format_double(1e20));
  EXPECT_EQ("0.30000000000000004", format_double(0.1 + 0.2));
  EXPECT_EQ(Value::real(1.0), parse_number("1.0").value());
  EXPECT_EQ(Value::integer(1), parse_number("1").value());
}

TEST(Fields, NumbersFollowTheGrammar) {
  EXPECT_EQ(Value::integer(-42), parse_number("-42").value());
  EXPECT_EQ(Value::real(1500.0), parse_number("1.5E3").value());
  EXPECT_EQ(Value::real(-0.0025), parse_number("-2.5e-3").value());
  EXPECT_EQ(Value::integer(std::numeric_limits<std::int64_t>::min()), parse_number("-9223372036854775808").value());
  for (std::string_view bad : {"", "-", "+1", ".5", "1.", "1e", "1e+", "0x10", "nan", "inf", "-inf", "NaN", "infinity",
                               "1_000", "1.2.3", "--1", "1e1.5"}) {
    EXPECT_FALSE(parse_number(bad).ok()) << bad;
  }
  EXPECT_EQ("integer '9223372036854775808' is out of range", parse_number("9223372036854775808").error().message);
  EXPECT_EQ("number '1e999' is out of range", parse_number("1e999").error().message);
  EXPECT_FALSE(parse_number("1e-999").ok());
  EXPECT_EQ(30.0, parse_double("30"));
}

TEST(Fields, IdsArePositiveAndFitInt64) {
  EXPECT_EQ(1u, parse_id("1"));
  EXPECT_EQ(kMaxRequestId, parse_id("9223372036854775807"));
  EXPECT_EQ(std::nullopt, parse_id("9223372036854775808"));
  EXPECT_EQ(std::nullopt, parse_id("18446744073709551616"));
  EXPECT_EQ(std::nullopt, parse_id("0"));
  EXPECT_EQ(0u, parse_id("0", true));
  for (std::string_view bad : {"", "-1", "+1", "1.0", "1e3", "abc", " 1"}) {
    EXPECT_EQ(std::nullopt, parse_id(bad)) << bad;
  }
}

RC_GTEST_PROP(Fields, EveryFiniteDoubleRoundTripsExactly, ()) {
  const double d = *rc::gen::suchThat(rc::gen::arbitrary<double>(), [](double x) { return std::isfinite(x); });
  const std::string text = format_double(d);
  core::Result<Value> back = parse_number(text);
  RC_ASSERT(back.ok());
  RC_ASSERT(back.value().kind() == Value::Kind::Float);
  RC_ASSERT(std::signbit(back.value().as_float()) == std::signbit(d));
  RC_ASSERT(back.value().as_float() == d);
}

RC_GTEST_PROP(Fields, QuoteOfAnyBytesSplitsBackToOneField, (const std::string& text)) {
  SplitResult s = split_fields(quote(text));
  RC_ASSERT(s.ok());
  RC_ASSERT(s.fields.size() == 1u);
  RC_ASSERT(s.fields[0].text.size() == text.size());
}

}  // namespace
}  // namespace strata::protocol
