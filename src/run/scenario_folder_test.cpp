#include "run/scenario_folder.h"

#include <sys/stat.h>
#include <unistd.h>

#include <fstream>

#include <gtest/gtest.h>

namespace strata::run {
namespace {

namespace fs = std::filesystem;

TEST(ScenarioFolder, IsScenariosBesideTheMissionRelativeStayingRelative) {
  EXPECT_EQ("tank/scenarios", scenarios_folder("tank/tank.coral").generic_string());
  EXPECT_EQ("scenarios", scenarios_folder("tank.coral").generic_string());
  EXPECT_EQ("/m/tank/scenarios", scenarios_folder("/m/tank/tank.pl").generic_string());
  EXPECT_EQ("tank/scenarios/leak_phase2.toml", scenario_path("tank/tank.coral", "leak_phase2").generic_string());
}

class ScenarioNames : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("strata_scenario_folder_test_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "scenarios");
  }
  void TearDown() override { fs::remove_all(dir_); }
  void touch(const std::string& name) { std::ofstream(dir_ / "scenarios" / name) << "seed = 1\n"; }
  fs::path dir_;
};

TEST_F(ScenarioNames, AreTheTomlFilesSortedWithoutTheirExtension) {
  touch("nominal.toml");
  touch("leak_phase2.toml");
  touch("notes.txt");
  fs::create_directories(dir_ / "scenarios/folder.toml");
  ASSERT_EQ(0, ::mkfifo((dir_ / "scenarios/pipe.toml").c_str(), 0600));
  EXPECT_EQ((std::vector<std::string>{"leak_phase2", "nominal"}), scenario_names_in(dir_ / "scenarios"));
}

TEST_F(ScenarioNames, AreNoneWhenTheFolderIsMissing) {
  EXPECT_TRUE(scenario_names_in(dir_ / "no_such_folder").empty());
  EXPECT_TRUE(scenario_names_in(scenarios_folder((dir_ / "elsewhere/m.coral").string())).empty());
}

}  // namespace
}  // namespace strata::run
