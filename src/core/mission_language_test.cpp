#include "core/mission_language.h"

#include <gtest/gtest.h>

namespace strata::core {
namespace {

TEST(MissionLanguage, TheExtensionDecides) {
  EXPECT_EQ(MissionLanguage::Coral, mission_language("missions/tank/tank.coral"));
  EXPECT_EQ(MissionLanguage::Prolog, mission_language("missions/tank/tank.pl"));
  EXPECT_EQ(MissionLanguage::Prolog, mission_language("/abs/dir.coral/rules.pl"));
  EXPECT_EQ(MissionLanguage::Coral, mission_language("tank.layout.coral"));
}

TEST(MissionLanguage, OtherFilesAreNoMission) {
  EXPECT_EQ(MissionLanguage::None, mission_language("scenario.toml"));
  EXPECT_EQ(MissionLanguage::None, mission_language("run.jsonl"));
  EXPECT_EQ(MissionLanguage::None, mission_language("tank.coral.layout.json"));
  EXPECT_EQ(MissionLanguage::None, mission_language("tank.PL"));
  EXPECT_EQ(MissionLanguage::None, mission_language("dir/.pl"));  // a hidden file named .pl: no extension
  EXPECT_EQ(MissionLanguage::None, mission_language("missions/tank/"));
  EXPECT_EQ(MissionLanguage::None, mission_language(""));
}

TEST(MissionLanguage, NamesAndExtensions) {
  EXPECT_EQ("coral", language_key(MissionLanguage::Coral));
  EXPECT_EQ("prolog", language_key(MissionLanguage::Prolog));
  EXPECT_EQ("", language_key(MissionLanguage::None));
  EXPECT_EQ("PROLOG", language_title(MissionLanguage::Prolog));
  EXPECT_EQ(".pl", mission_extension(MissionLanguage::Prolog));
  EXPECT_EQ(".coral", mission_extension(MissionLanguage::Coral));
}

}  // namespace
}  // namespace strata::core
