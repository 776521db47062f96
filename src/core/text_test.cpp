#include "core/text.h"

#include <gtest/gtest.h>

namespace strata::core {
namespace {

TEST(Shorten, LeavesShortTextAlone) {
  EXPECT_EQ("depth", shorten("depth", 5, "..."));
  EXPECT_EQ("", shorten("", 0, "..."));
}

TEST(Shorten, CutsAndMarksLongText) {
  EXPECT_EQ("dep...", shorten("depth reached", 3, "..."));
  EXPECT_EQ(" ...", shorten("x", 0, " ..."));
}

TEST(Shorten, NeverCutsInsideAUtf8Character) {
  // "é" is two bytes (C3 A9): a cut after its first byte backs up before it.
  EXPECT_EQ("ab...", shorten("ab\xC3\xA9z", 3, "..."));
  EXPECT_EQ("ab\xC3\xA9...", shorten("ab\xC3\xA9z", 4, "..."));
  // "→" is three bytes (E2 86 92).
  EXPECT_EQ("a...", shorten("a\xE2\x86\x92", 3, "..."));
}

TEST(ValidUtf8, TakesWellFormedTextAndRefusesEveryMalformedKind) {
  EXPECT_TRUE(valid_utf8(""));
  EXPECT_TRUE(valid_utf8("tank.coral"));
  EXPECT_TRUE(valid_utf8("plongée/été.coral"));   // 2 bytes
  EXPECT_TRUE(valid_utf8("\xe6\xb5\xb7.coral"));  // 3 bytes (海)
  EXPECT_TRUE(valid_utf8("\xf0\x9f\x90\x8b"));    // 4 bytes (a whale)
  EXPECT_FALSE(valid_utf8("caf\xe9.coral"));      // Latin-1
  EXPECT_FALSE(valid_utf8("\xc0\xaf"));           // overlong '/'
  EXPECT_FALSE(valid_utf8("\xe0\x80\xaf"));       // overlong, 3 bytes
  EXPECT_FALSE(valid_utf8("\xed\xa0\x80"));       // a surrogate
  EXPECT_FALSE(valid_utf8("\xf4\x90\x80\x80"));   // past U+10FFFF
  EXPECT_FALSE(valid_utf8("\xe6\xb5"));           // cut short
  EXPECT_FALSE(valid_utf8("\x80"));               // a lone continuation byte
}

TEST(Suggest, OnlyCloseNames) {
  EXPECT_EQ("depth_reached", suggest("depth_reachd", {"time_out", "depth_reached"}));
  EXPECT_FALSE(suggest("xyz", {"depth_reached"}));
}

TEST(Suggest, TwoLettersSwappedAreOneTypo) {
  EXPECT_EQ("run", suggest("rnu", {"check", "run", "dump"}));
  EXPECT_EQ("verify", suggest("verfiy", {"run", "verify"}));
  EXPECT_FALSE(suggest("nur", {"run"}));  // a reversal is two swaps, too far for three letters
}

}  // namespace
}  // namespace strata::core
