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

}  // namespace
}  // namespace strata::core
