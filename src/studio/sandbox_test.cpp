#include "studio/sandbox.h"

#include <stdlib.h>

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

namespace strata::studio {
namespace {

namespace fs = std::filesystem;

class SandboxTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = (fs::path(::testing::TempDir()) / "strata_sandbox_XXXXXX").string();
    ASSERT_NE(nullptr, mkdtemp(pattern.data()));
    base_ = pattern;
    fs::create_directories(base_ / "root/missions");
    std::ofstream(base_ / "root/missions/a.coral") << "net a {}";
    std::ofstream(base_ / "secret.txt") << "outside";
    fs::create_symlink(base_ / "secret.txt", base_ / "root/missions/link.coral");
    fs::create_directory_symlink(base_, base_ / "root/up");
  }
  void TearDown() override { fs::remove_all(base_); }
  fs::path base_;
};

TEST_F(SandboxTest, ResolvesAFileInside) {
  Sandbox s(base_ / "root");
  auto r = s.resolve("missions/a.coral");
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(fs::canonical(base_ / "root/missions/a.coral"), r.value());
  EXPECT_EQ("missions/a.coral", s.relative(r.value()));
}

TEST_F(SandboxTest, RefusesEveryWayOut) {
  Sandbox s(base_ / "root");
  for (const char* bad : {"../secret.txt", "missions/../../secret.txt", "/etc/passwd", "", "missions\\a.coral",
                          "missions/link.coral", "up/secret.txt"}) {
    auto r = s.resolve(bad);
    ASSERT_FALSE(r.ok()) << bad;
    EXPECT_EQ(core::ErrorCode::InvalidInput, r.error().code) << bad << ": " << r.error().message;
  }
  // Writing: through a link to a folder outside, or onto a link outside.
  EXPECT_FALSE(s.resolve("up/new.coral", true).ok());
  EXPECT_FALSE(s.resolve("missions/link.coral", true).ok());
  EXPECT_TRUE(s.resolve("missions/new.coral", true).ok());
  EXPECT_EQ(core::ErrorCode::Io, s.resolve("missions/none.coral").error().code);
}

TEST_F(SandboxTest, ListsOnlyFilesInside) {
  Sandbox s(base_ / "root");
  EXPECT_EQ(std::vector<std::string>({"missions/a.coral"}), s.list({".coral"}));
}

}  // namespace
}  // namespace strata::studio
