// RunOptions::keep_mission for CORAL: a campaign's worker compiles and
// verifies a mission once, and takes it back only while every file the
// compile read still reads the same.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "run/loaded_mission.h"
#include "run/options.h"

namespace strata::run {
namespace {

namespace fs = std::filesystem;

class KeptMission : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("strata-kept-" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    for (const char* f : {"tank.coral", "initialize.coral", "dive_from_surface.coral", "submerge_to_depth.coral",
                          "return_to_surface.coral", "setpoints.toml"}) {
      fs::copy_file(fs::path(STRATA_SOURCE_DIR) / "missions/tank" / f, dir_ / f);
    }
  }
  void TearDown() override { fs::remove_all(dir_); }

  RunOptions options(bool keep = true) const {
    RunOptions o;
    o.mission = (dir_ / "tank.coral").string();
    o.keep_mission = keep;
    return o;
  }

  void append(const char* file, const std::string& text) const {
    std::ofstream out(dir_ / file, std::ios::app);
    out << text;
  }

  fs::path dir_;
};

TEST_F(KeptMission, ACoralMissionLoadedAgainIsTakenBackWithItsVerification) {
  LoadedMission first;
  ASSERT_TRUE(load_mission(options(), first).ok());
  EXPECT_FALSE(first.taken_back);
  LoadedMission second;
  ASSERT_TRUE(load_mission(options(), second).ok());
  EXPECT_TRUE(second.taken_back);
  ASSERT_TRUE(second.program && second.verification);
  EXPECT_EQ(first.program->nets.size(), second.program->nets.size());
  EXPECT_EQ(first.name, second.name);
  EXPECT_EQ(first.verification->ok(), second.verification->ok());
  EXPECT_EQ(first.sources.size(), second.sources.size());
}

TEST_F(KeptMission, AnEditedImportIsCompiledAgainAndItsErrorStopsTheRun) {
  LoadedMission first;
  ASSERT_TRUE(load_mission(options(), first).ok());
  append("dive_from_surface.coral", "\nnet broken { place\n");
  LoadedMission second;
  const auto r = load_mission(options(), second);
  ASSERT_FALSE(r.ok());
  EXPECT_FALSE(second.taken_back);
  EXPECT_NE(std::string::npos, r.error().message.find("not running")) << r.error().message;
  ASSERT_TRUE(r.error().place);
  EXPECT_NE(std::string::npos, r.error().place->file.find("dive_from_surface.coral")) << r.error().place->file;
}

TEST_F(KeptMission, AnImportEditedWithoutErrorIsCompiledAgainNotTakenBack) {
  LoadedMission first;
  ASSERT_TRUE(load_mission(options(), first).ok());
  append("initialize.coral", "\n// an edit\n");
  LoadedMission second;
  ASSERT_TRUE(load_mission(options(), second).ok());
  EXPECT_FALSE(second.taken_back);
  LoadedMission third;
  ASSERT_TRUE(load_mission(options(), third).ok());
  EXPECT_TRUE(third.taken_back);
}

TEST_F(KeptMission, WithoutKeepMissionEveryLoadCompiles) {
  for (int i = 0; i < 2; ++i) {
    LoadedMission loaded;
    ASSERT_TRUE(load_mission(options(false), loaded).ok());
    EXPECT_FALSE(loaded.taken_back);
  }
}

TEST_F(KeptMission, AMissionReadThroughAReaderIsComparedThroughIt) {
  RunOptions o = options();
  std::string extra;
  o.read_file = [&extra](const std::string& path) -> core::Result<std::string> {
    std::ifstream in(path);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in && !in.eof()) return core::Error{core::ErrorCode::Io, "cannot read " + path};
    return path.ends_with("initialize.coral") ? text + extra : text;
  };
  LoadedMission first;
  ASSERT_TRUE(load_mission(o, first).ok());
  extra = "\n// read differently\n";
  LoadedMission second;
  ASSERT_TRUE(load_mission(o, second).ok());
  EXPECT_FALSE(second.taken_back);
}

}  // namespace
}  // namespace strata::run
