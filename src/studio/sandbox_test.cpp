#include "studio/sandbox.h"

#include <stdlib.h>
#include <sys/stat.h>

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

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

// Issue 17: a link planted at the old temporary name was written through.
TEST_F(SandboxTest, WriteDoesNotFollowALinkPlantedAtTheTemporaryName) {
  Sandbox s(base_ / "root");
  fs::create_symlink("../../secret.txt", base_ / "root/missions/a.coral.strata-tmp");
  auto w = s.write("missions/a.coral", "net b {}");
  ASSERT_TRUE(w.ok()) << w.error().message;
  EXPECT_EQ("outside", slurp(base_ / "secret.txt"));
  EXPECT_EQ("net b {}", slurp(base_ / "root/missions/a.coral"));
  EXPECT_FALSE(fs::is_symlink(base_ / "root/missions/a.coral"));
  // No temporary file is left behind (the planted link stays).
  int entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(base_ / "root/missions")) ++entries;
  EXPECT_EQ(3, entries);  // a.coral, link.coral, the planted link
}

TEST_F(SandboxTest, WriteRefusesATargetLinkedOutside) {
  Sandbox s(base_ / "root");
  auto w = s.write("missions/link.coral", "net b {}");
  ASSERT_FALSE(w.ok());
  EXPECT_EQ(core::ErrorCode::InvalidInput, w.error().code);
  EXPECT_EQ("outside", slurp(base_ / "secret.txt"));
  EXPECT_TRUE(fs::is_symlink(base_ / "root/missions/link.coral"));
  EXPECT_FALSE(s.write("up/secret.txt", "x").ok());
  EXPECT_FALSE(s.write("../secret.txt", "x").ok());
  EXPECT_EQ("outside", slurp(base_ / "secret.txt"));
}

TEST_F(SandboxTest, WriteThroughALinkInsideReplacesTheFileItNames) {
  Sandbox s(base_ / "root");
  fs::create_symlink("a.coral", base_ / "root/missions/alias.coral");
  ASSERT_TRUE(s.write("missions/alias.coral", "net c {}").ok());
  EXPECT_TRUE(fs::is_symlink(base_ / "root/missions/alias.coral"));
  EXPECT_EQ("net c {}", slurp(base_ / "root/missions/a.coral"));
}

TEST_F(SandboxTest, WriteRefusesATargetThatIsNotARegularFile) {
  Sandbox s(base_ / "root");
  fs::create_directory(base_ / "root/missions/dir.coral");
  auto w = s.write("missions/dir.coral", "x");
  ASSERT_FALSE(w.ok());
  EXPECT_EQ(core::ErrorCode::InvalidInput, w.error().code);
}

TEST_F(SandboxTest, ReadsOnlyRegularFilesInside) {
  Sandbox s(base_ / "root");
  auto a = s.read("missions/a.coral");
  ASSERT_TRUE(a.ok()) << a.error().message;
  EXPECT_EQ("net a {}", a.value());
  EXPECT_EQ(core::ErrorCode::InvalidInput, s.read("missions/link.coral").error().code);
  EXPECT_EQ(core::ErrorCode::InvalidInput, s.read_path("/etc/passwd").error().code);
  EXPECT_EQ(core::ErrorCode::InvalidInput, s.read_path(base_ / "root/missions/../../secret.txt").error().code);
  EXPECT_EQ(core::ErrorCode::InvalidInput, s.read_path(base_ / "root/up/secret.txt").error().code);
  EXPECT_NE(std::string::npos, s.read_path("/etc/passwd").error().message.find("outside the studio's folder"));
  EXPECT_EQ("net a {}", s.read_path(base_ / "root/missions/a.coral").value());
  EXPECT_EQ(core::ErrorCode::Io, s.read_path(base_ / "root/missions/none.coral").error().code);
  // A FIFO under a mission's name is refused, not waited on.
  ASSERT_EQ(0, ::mkfifo((base_ / "root/missions/fifo.coral").c_str(), 0600));
  EXPECT_EQ(core::ErrorCode::InvalidInput, s.read("missions/fifo.coral").error().code);
  EXPECT_EQ(core::ErrorCode::Overflow, s.read("missions/a.coral", 3).error().code);
}

}  // namespace
}  // namespace strata::studio
