#include "core/file.h"

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

namespace strata::core {
namespace {

namespace fs = std::filesystem;

class ReadRegularFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("strata_file_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }
  fs::path dir_;
};

TEST_F(ReadRegularFile, ReadsTheWholeFile) {
  auto r = read_regular_file(write("a.pl", "mission :- true.\n"), 1024);
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(r.value(), "mission :- true.\n");
}

TEST_F(ReadRegularFile, AFileOfExactlyTheLimitIsRead) {
  auto r = read_regular_file(write("a.pl", std::string(100, 'x')), 100);
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(r.value().size(), 100u);
}

TEST_F(ReadRegularFile, AFileOverTheLimitIsRefusedNamingTheLimit) {
  auto r = read_regular_file(write("a.pl", std::string(101, 'x')), 100);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::Overflow);
  EXPECT_NE(r.error().message.find("limit of 100 bytes"), std::string::npos) << r.error().message;
}

TEST_F(ReadRegularFile, AFifoIsRefusedNotWaitedOn) {
  const fs::path fifo = dir_ / "pipe.pl";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  auto r = read_regular_file(fifo.string(), 1024);  // no writer: a blocking open would never return
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::Io);
  EXPECT_NE(r.error().message.find("not a regular file"), std::string::npos) << r.error().message;
}

TEST_F(ReadRegularFile, AFolderIsRefused) {
  auto r = read_regular_file(dir_.string(), 1024);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("not a regular file"), std::string::npos) << r.error().message;
}

TEST_F(ReadRegularFile, AMissingFileIsAnIoError) {
  auto r = read_regular_file((dir_ / "nosuch.pl").string(), 1024);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::Io);
  EXPECT_NE(r.error().message.find("nosuch.pl"), std::string::npos);
}

}  // namespace
}  // namespace strata::core
