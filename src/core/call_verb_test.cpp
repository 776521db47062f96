#include "core/call_verb.h"

#include <set>
#include <string>

#include <gtest/gtest.h>

namespace strata::core {
namespace {

TEST(CallVerb, EveryVerbRoundTripsThroughItsName) {
  std::set<std::string_view> names;
  for (CallVerb v : kCallVerbs) {
    names.insert(call_verb_name(v));
    EXPECT_EQ(v, parse_call_verb(call_verb_name(v))) << call_verb_name(v);
  }
  EXPECT_EQ(kCallVerbs.size(), names.size()) << "one name per verb";
  EXPECT_EQ("exec", call_verb_name(CallVerb::Exec));
  EXPECT_EQ("report", call_verb_name(CallVerb::Report));
}

TEST(CallVerb, ATypoOrAnotherSpellingIsNoVerb) {
  for (std::string_view bad : {"", "exe", "EXEC", "Ask", "phase", "hello", "ping", "exec "}) {
    EXPECT_FALSE(parse_call_verb(bad).has_value()) << bad;
  }
}

}  // namespace
}  // namespace strata::core
