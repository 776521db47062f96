#include "core/file.h"

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include <fmt/format.h>
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

// A regular file whose size says 0 but that has text (/proc's): the buffer
// starts one byte past the size and grows as the text comes.
TEST_F(ReadRegularFile, AFileLongerThanItsSizeSaysIsReadWhole) {
  auto r = read_regular_file("/proc/self/status", std::size_t{1} << 20);
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_NE(r.value().find("Name:"), std::string::npos);
  EXPECT_NE(r.value().find("VmPeak:"), std::string::npos);  // past the first byte
}

TEST_F(ReadRegularFile, AnEmptyFileIsReadEmpty) {
  auto r = read_regular_file(write("a.pl", ""), 100);
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_TRUE(r.value().empty());
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

// A file named x.coral must be one once its links are resolved: a mission
// folder's link phases.coral -> a secret had its lines shown in syntax
// errors (coral::DiskFileProvider, a campaign's cases).
TEST_F(ReadRegularFile, ALinkNamedForOneKindToAFileOfAnotherIsRefusedNamingItsTarget) {
  const std::string secret = write("secret.txt", "TOKEN=abc\n");
  fs::create_symlink(secret, dir_ / "phases.coral");
  auto r = read_regular_file_as_named((dir_ / "phases.coral").string(), 1024, ".coral");
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::Io);
  EXPECT_EQ(r.error().message.find("TOKEN"), std::string::npos);
  EXPECT_NE(r.error().message.find("is a link to '" + fs::canonical(secret).string() + "', which is not a .coral file"),
            std::string::npos)
      << r.error().message;
}

TEST_F(ReadRegularFile, ALinkToAFileOfTheKindItsNameSaysIsRead) {
  const std::string shared = write("shared.coral", "net n { }\n");
  fs::create_symlink(shared, dir_ / "linked.coral");
  auto r = read_regular_file_as_named((dir_ / "linked.coral").string(), 1024, ".coral");
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(r.value(), "net n { }\n");
  auto plain = read_regular_file_as_named(write("data.toml", "a = 1\n"), 1024, ".coral");  // another kind: as named
  ASSERT_TRUE(plain) << plain.error().message;
}

// Resolving the links by name (std::filesystem::weakly_canonical) fails
// once a path passes PATH_MAX, which the kernel, following one link at a
// time, does not mind: a chain of links through long folder names got a
// secret read as phases.coral. The open file's own name is asked instead;
// when even that cannot be told, the file is refused.
TEST_F(ReadRegularFile, ALinkThroughPathsLongerThanTheSystemResolvesIsStillCheckedOrRefused) {
  const std::string secret = fs::canonical(write("secret.txt", "TOKEN=abc\n")).string();
  // 20 folders of 250-character names, made one inside the other (a path
  // that long cannot be named whole); links relative to their folders, each
  // under PATH_MAX: phases.coral -> 10 levels/y, y -> 10 more levels/z, z ->
  // the secret.
  std::vector<int> fds{::open(dir_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC)};
  std::string first_half, second_half;
  for (int i = 0; i < 20; ++i) {
    const std::string name(250, static_cast<char>('a' + i));
    ASSERT_EQ(0, ::mkdirat(fds.back(), name.c_str(), 0700)) << std::strerror(errno);
    fds.push_back(::openat(fds.back(), name.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
    ASSERT_GE(fds.back(), 0) << std::strerror(errno);
    (i < 10 ? first_half : second_half) += name + "/";
  }
  ASSERT_EQ(0, ::symlinkat(secret.c_str(), fds[20], "z"));
  ASSERT_EQ(0, ::symlinkat((second_half + "z").c_str(), fds[10], "y"));
  ASSERT_EQ(0, ::symlinkat((first_half + "y").c_str(), fds[0], "phases.coral"));
  for (int fd : fds) ::close(fd);
  // The kernel follows it to the secret; naming where it leads fails.
  std::error_code ec;
  const fs::path resolved = fs::weakly_canonical(dir_ / "phases.coral", ec);
  EXPECT_TRUE(ec) << "resolved to " << resolved << ": the case no longer reaches past PATH_MAX";
  auto r = read_regular_file_as_named((dir_ / "phases.coral").string(), 1024, ".coral");
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::Io);
  EXPECT_EQ(r.error().message.find("TOKEN"), std::string::npos);
  EXPECT_TRUE(r.error().message.find("which is not a .coral file") != std::string::npos ||
              r.error().message.find("cannot be told") != std::string::npos)
      << r.error().message;
  // The folders' names are too long for remove_all to name them whole.
  ASSERT_EQ(0, ::system(fmt::format("rm -rf '{}'", dir_.string()).c_str()));
}

class WriteFileAtomically : public ReadRegularFile {
 protected:
  static std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
  }
  // The names in the test's folder, sorted: a temporary file left behind
  // shows up here.
  std::string names() const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir_)) out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    std::string joined;
    for (const auto& n : out) joined += (joined.empty() ? "" : " ") + n;
    return joined;
  }
  static mode_t mode_of(const fs::path& p) {
    struct stat st {};
    EXPECT_EQ(0, ::lstat(p.c_str(), &st));
    return st.st_mode & 07777;
  }
  static mode_t umask_now() {
    const mode_t m = ::umask(022);
    ::umask(m);
    return m;
  }
};

TEST_F(WriteFileAtomically, CreatesTheFileWithMode0644LessTheUmask) {
  const fs::path p = dir_ / "out.dot";
  auto w = write_file_atomically(p.string(), "digraph {}\n");
  ASSERT_TRUE(w) << w.error().message;
  EXPECT_EQ("digraph {}\n", slurp(p));
  EXPECT_EQ(0644 & ~umask_now(), mode_of(p));
  EXPECT_EQ("out.dot", names());
}

TEST_F(WriteFileAtomically, ReplacesAnExistingFileAndLeavesNoTemporaryFile) {
  const std::string p = write("report.json", "old, and longer than the new");
  auto w = write_file_atomically(p, "new");
  ASSERT_TRUE(w) << w.error().message;
  EXPECT_EQ("new", slurp(p));
  EXPECT_EQ("report.json", names());
}

TEST_F(WriteFileAtomically, AGivenModeIsTheNewFilesAndKeepExistingModeKeepsTheOld) {
  const fs::path script = dir_ / "run.sh";
  ASSERT_TRUE(write_file_atomically(script.string(), "#!/bin/sh\n", {.mode = 0755}));
  EXPECT_EQ(0755 & ~umask_now(), mode_of(script));
  ::chmod(script.c_str(), 0700);
  ASSERT_TRUE(write_file_atomically(script.string(), "#!/bin/sh\ntrue\n", {.keep_existing_mode = true}));
  EXPECT_EQ(0700, mode_of(script));
  ASSERT_TRUE(write_file_atomically(script.string(), "#!/bin/sh\n"));
  EXPECT_EQ(0644 & ~umask_now(), mode_of(script));
}

TEST_F(WriteFileAtomically, AFifoTargetIsRefusedWithoutBlocking) {
  const fs::path fifo = dir_ / "pipe.json";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  auto w = write_file_atomically(fifo.string(), "{}");  // no reader: opening it to write would block
  ASSERT_FALSE(w);
  EXPECT_EQ(ErrorCode::Io, w.error().code);
  EXPECT_NE(w.error().message.find("a FIFO"), std::string::npos) << w.error().message;
  EXPECT_TRUE(fs::is_fifo(fs::symlink_status(fifo)));
  EXPECT_EQ("pipe.json", names());
}

TEST_F(WriteFileAtomically, ASymlinkTargetIsNotWrittenThroughIntoAnotherFolder) {
  const fs::path other = dir_ / "other";
  fs::create_directories(other);
  std::ofstream(other / "victim") << "precious";
  fs::create_directories(dir_ / "out");
  fs::create_symlink("../other/victim", dir_ / "out/report.html");
  auto w = write_file_atomically((dir_ / "out/report.html").string(), "<html>");
  ASSERT_FALSE(w);
  EXPECT_EQ(ErrorCode::Io, w.error().code);
  EXPECT_NE(w.error().message.find("a symbolic link"), std::string::npos) << w.error().message;
  EXPECT_EQ("precious", slurp(other / "victim"));
  EXPECT_TRUE(fs::is_symlink(dir_ / "out/report.html"));
  EXPECT_EQ(1, std::distance(fs::directory_iterator(dir_ / "out"), fs::directory_iterator()));
}

TEST_F(WriteFileAtomically, ADanglingSymlinkTargetIsRefusedAndNothingIsCreatedWhereItPoints) {
  fs::create_symlink("created-through-the-link", dir_ / "out.png");
  ASSERT_FALSE(write_file_atomically((dir_ / "out.png").string(), "png"));
  EXPECT_FALSE(fs::exists(dir_ / "created-through-the-link"));
  EXPECT_EQ("out.png", names());
}

TEST_F(WriteFileAtomically, AFolderTargetIsRefusedAndKept) {
  fs::create_directories(dir_ / "man");
  auto w = write_file_atomically((dir_ / "man").string(), "x");
  ASSERT_FALSE(w);
  EXPECT_NE(w.error().message.find("a folder"), std::string::npos) << w.error().message;
  EXPECT_TRUE(fs::is_directory(dir_ / "man"));
  EXPECT_FALSE(write_file_atomically(dir_.string() + "/", "x"));
  EXPECT_EQ("man", names());
}

TEST_F(WriteFileAtomically, AFailedWriteLeavesTheOldContentAndNoTemporaryFile) {
  const std::string p = write("frame.png", "the old frame");
  // The file size limit makes write(2) fail with EFBIG part way (SIGXFSZ,
  // which would end the process, is ignored for the test).
  rlimit old{};
  ASSERT_EQ(0, ::getrlimit(RLIMIT_FSIZE, &old));
  auto* old_handler = std::signal(SIGXFSZ, SIG_IGN);
  rlimit small = old;
  small.rlim_cur = 1024;
  ASSERT_EQ(0, ::setrlimit(RLIMIT_FSIZE, &small));
  auto w = write_file_atomically(p, std::string(8192, 'x'));
  ::setrlimit(RLIMIT_FSIZE, &old);
  std::signal(SIGXFSZ, old_handler);
  ASSERT_FALSE(w);
  EXPECT_EQ(ErrorCode::Io, w.error().code);
  EXPECT_NE(w.error().message.find(p), std::string::npos) << w.error().message;
  EXPECT_NE(w.error().message.find(std::strerror(EFBIG)), std::string::npos) << w.error().message;
  EXPECT_EQ("the old frame", slurp(p));
  EXPECT_EQ("frame.png", names());
}

TEST_F(WriteFileAtomically, AMissingFolderIsAnIoErrorNamingThePathAndTheReason) {
  const std::string p = (dir_ / "no_such_dir/out.dot").string();
  auto w = write_file_atomically(p, "x");
  ASSERT_FALSE(w);
  EXPECT_EQ(ErrorCode::Io, w.error().code);
  EXPECT_EQ(fmt::format("cannot write '{}': {}", p, std::strerror(ENOENT)), w.error().message);
}

TEST_F(WriteFileAtomically, WritesAnEntryOfAnOpenFolder) {
  const int dir = ::open(dir_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  ASSERT_GE(dir, 0);
  auto w = write_file_atomically_at(dir, "a.coral", "net a {}", "missions/a.coral");
  ::close(dir);
  ASSERT_TRUE(w) << w.error().message;
  EXPECT_EQ("net a {}", slurp(dir_ / "a.coral"));
  EXPECT_EQ("a.coral", names());
}

}  // namespace
}  // namespace strata::core
