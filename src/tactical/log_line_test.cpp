// LogLine writes, field by field, what dumping the same ordered_json gives:
// the log's bytes did not change when its busiest lines stopped building
// JSON values.
#include "tactical/log_line.h"

#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace strata::tactical {
namespace {

using nlohmann::ordered_json;

std::string dumped(const ordered_json& j) {
  return j.dump(-1, ' ', false, ordered_json::error_handler_t::replace) + "\n";
}

double from_bits(std::uint64_t bits) {
  double d = 0;
  std::memcpy(&d, &bits, sizeof d);
  return d;
}

TEST(LogLine, NumbersAreWrittenAsTheJsonDumpWritesThem) {
  const std::vector<double> values = {0.0,
                                      -0.0,
                                      1.0,
                                      26.0,
                                      0.1,
                                      -0.0412,
                                      1e-5,
                                      1e-7,
                                      123456.789,
                                      1e15,
                                      1e16,
                                      1e17,
                                      1e21,
                                      1e22,
                                      -1e300,
                                      5e-324,
                                      0.5,
                                      2.5e-4,
                                      1e-4,
                                      9.999e-5,
                                      1234567890123456789.0,
                                      3.141592653589793,
                                      std::numeric_limits<double>::max(),
                                      std::numeric_limits<double>::min(),
                                      std::numeric_limits<double>::infinity(),
                                      std::numeric_limits<double>::quiet_NaN()};
  for (double v : values) {
    LogLine line("x");
    line.add("v", v);
    ordered_json j;
    j["event"] = "x";
    j["v"] = v;
    EXPECT_EQ(dumped(j), std::move(line).finish()) << v;
  }
}

TEST(LogLine, IntegersAtTheirLimitsAreWrittenAsTheJsonDumpWritesThem) {
  LogLine line("x");
  line.add("a", std::numeric_limits<std::int64_t>::min())
      .add("b", std::numeric_limits<std::int64_t>::max())
      .add("c", std::numeric_limits<std::uint64_t>::max())
      .add("d", 0)
      .add("e", -1)
      .add("f", std::uint32_t{4'000'000'000u});
  ordered_json j;
  j["event"] = "x";
  j["a"] = std::numeric_limits<std::int64_t>::min();
  j["b"] = std::numeric_limits<std::int64_t>::max();
  j["c"] = std::numeric_limits<std::uint64_t>::max();
  j["d"] = 0;
  j["e"] = -1;
  j["f"] = std::uint32_t{4'000'000'000u};
  EXPECT_EQ(dumped(j), std::move(line).finish());
}

TEST(LogLine, TextWithQuotesControlsAndInvalidUtf8IsEscapedAsTheJsonDumpDoesIt) {
  const std::vector<std::string> texts = {"",   "plain",        "a \"quoted\" word", "back\\slash", "tab\there",
                                          "\n", "\x01\x1f\x7f", "caf\xc3\xa9",       "\xff\xfe",    "bad \xc3 end"};
  for (const std::string& s : texts) {
    LogLine line("x");
    line.add("s", s).begin_object(s).add(s, 1).end_object();
    ordered_json j;
    j["event"] = "x";
    j["s"] = s;
    j[s] = ordered_json::object();
    j[s][s] = 1;
    // A key equal to "s" would collide: the texts above never are.
    EXPECT_EQ(dumped(j), std::move(line).finish()) << s;
  }
}

TEST(LogLine, NestedObjectsAndJsonValuesKeepTheirOrder) {
  LogLine line("fire");
  line.add("n", 3).begin_object("consumed").add("a", 1).add("b", 2).end_object();
  line.begin_object("produced").end_object().add("result", ordered_json{{"error", "timeout"}}).add_null("z");
  ordered_json j;
  j["event"] = "fire";
  j["n"] = 3;
  j["consumed"] = {{"a", 1}, {"b", 2}};
  j["produced"] = ordered_json::object();
  j["result"] = {{"error", "timeout"}};
  j["z"] = nullptr;
  EXPECT_EQ(dumped(j), std::move(line).finish());
}

RC_GTEST_PROP(LogLine, AnyDoubleIsWrittenAsTheJsonDumpWritesIt, (std::uint64_t bits)) {
  const double v = from_bits(bits);
  LogLine line("x");
  line.add("v", v);
  ordered_json j;
  j["event"] = "x";
  j["v"] = v;
  RC_ASSERT(dumped(j) == std::move(line).finish());
}

RC_GTEST_PROP(LogLine, AnyTextIsWrittenAsTheJsonDumpWritesIt, ()) {
  // Any bytes: invalid UTF-8 and control characters too.
  const auto s = *rc::gen::container<std::string>(rc::gen::arbitrary<char>());
  LogLine line("x");
  line.add("text", s);
  ordered_json j;
  j["event"] = "x";
  j["text"] = s;
  RC_ASSERT(dumped(j) == std::move(line).finish());
}

}  // namespace
}  // namespace strata::tactical
