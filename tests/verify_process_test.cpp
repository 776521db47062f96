// `strata verify --pnml` as a process on a net too large to finish: Ctrl-C
// (SIGINT) and --max-memory both end it with a partial report and exit 1.
// `strata verify` and `check` on inputs a planner can write: a long chain
// mission ends within its limits (never exit 70); an import of a FIFO is
// refused at once.
#include <signal.h>
#include <stdlib.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "core/test_fifo.h"
#include "petri/net_families.h"
#include "petri/pnml.h"
#include "support/tank_run.h"

namespace strata::cli::run_testing {
namespace {

using namespace std::chrono_literals;

// --max-memory limits the whole process. Under AddressSanitizer a process
// holds far more before it starts (shadow memory, allocator metadata; about
// 110 MB for `strata verify` of a tiny net since the ASan build links
// -no-pie, 130 MB before), so the tests' limits get headroom there. With
// 160 MB, the 20 MB the -no-pie build saved let
// MaxMemoryEndsItWithAPartialReport's table take one more doubling (3.1
// million states, over its bound); at 120 MB it stops at 1.6 million, as
// it did before.
#if defined(__SANITIZE_ADDRESS__)
constexpr unsigned kSanitizerHeadroomMb = 120;
#else
constexpr unsigned kSanitizerHeadroomMb = 0;
#endif

// Under AddressSanitizer freed blocks stay resident in its quarantine (256 MB
// by default), which --max-memory then counts: the memory-limit tests run
// strata without it (each test is a process of its own).
// Under ThreadSanitizer every byte of heap has shadow bytes of its own, also
// resident (a 360 MB limit peaked at 1 GB): the memory-limit tests skip there
// (they run in the asan and dev presets; these are not threaded tests).
#if defined(__SANITIZE_THREAD__)
#define STRATA_SKIP_UNDER_TSAN() GTEST_SKIP() << "skipped under ThreadSanitizer: its shadow memory is resident too"
#else
#define STRATA_SKIP_UNDER_TSAN() static_cast<void>(0)
#endif

void without_asan_quarantine() {
#if defined(__SANITIZE_ADDRESS__)
  const char* old = getenv("ASAN_OPTIONS");
  const std::string options =
      (old != nullptr && *old != '\0' ? std::string(old) + ":" : std::string()) + "quarantine_size_mb=0";
  setenv("ASAN_OPTIONS", options.c_str(), 1);
#endif
}

// Referendum-17: 3^17 + 1 = 129,140,164 states, minutes of work.
std::string write_big_net(const TempDir& dir) {
  const std::string path = dir.file("referendum17.pnml");
  std::ofstream(path) << petri::write_pnml(petri::referendum(17), "referendum17");
  return path;
}

struct Finished {
  int status = -1;
  std::string out;
};

// Starts strata with args, stdout to a file; `during` runs while it works;
// waits up to 30 s for it to end (then kills it and fails).
template <typename During>
Finished run_strata(const TempDir& dir, std::vector<std::string> args, During during) {
  args.insert(args.begin(), STRATA_BINARY);
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const std::string out_path = dir.file("stdout.txt");
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  pid_t pid = -1;
  const int spawned = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  Finished f;
  if (spawned != 0) {
    ADD_FAILURE() << "cannot start " << argv[0];
    return f;
  }
  during(pid);
  const auto deadline = std::chrono::steady_clock::now() + 30s;
  while (waitpid(pid, &f.status, WNOHANG) != pid) {
    if (std::chrono::steady_clock::now() > deadline) {
      kill(pid, SIGKILL);
      waitpid(pid, &f.status, 0);
      ADD_FAILURE() << "strata did not end within 30 s";
      break;
    }
    std::this_thread::sleep_for(20ms);
  }
  f.out = read_file(out_path);
  return f;
}

// Whether pid has a handler for sig (Linux: /proc/PID/status, SigCgt).
bool catches(pid_t pid, int sig) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind("SigCgt:", 0) == 0) return (std::stoull(line.substr(7), nullptr, 16) >> (sig - 1)) & 1U;
  }
  return false;
}

// The SIGINT goes once strata takes it (its exploration has begun): a
// fixed 1.5 s was before that under ThreadSanitizer on a loaded machine.
TEST(VerifyProcess, CtrlCEndsALongExplorationWithAPartialReport) {
  TempDir dir;
  const std::string net = write_big_net(dir);
  Finished f = run_strata(dir, {"verify", "--pnml", net}, [](pid_t pid) {
    for (int i = 0; i < 1000 && !catches(pid, SIGINT); ++i) std::this_thread::sleep_for(20ms);
    std::this_thread::sleep_for(500ms);
    kill(pid, SIGINT);
  });
  ASSERT_TRUE(WIFEXITED(f.status)) << "ended by a signal: " << f.status;
  EXPECT_EQ(1, WEXITSTATUS(f.status)) << f.out;
  EXPECT_NE(std::string::npos, f.out.find("PARTIAL: interrupted after ")) << f.out;
  EXPECT_NE(std::string::npos, f.out.find("  states ")) << f.out;
}

TEST(VerifyProcess, MaxMemoryEndsItWithAPartialReport) {
  STRATA_SKIP_UNDER_TSAN();
  without_asan_quarantine();
  TempDir dir;
  const std::string net = write_big_net(dir);
  Finished f = run_strata(
      dir, {"verify", "--pnml", net, "--max-memory", std::to_string(16 + kSanitizerHeadroomMb), "--format", "json"},
      [](pid_t) {});
  ASSERT_TRUE(WIFEXITED(f.status)) << "ended by a signal: " << f.status;
  EXPECT_EQ(1, WEXITSTATUS(f.status)) << f.out;
  auto j = json::parse(f.out, nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << f.out;
  EXPECT_FALSE(j.at("complete").get<bool>());
  EXPECT_NE(std::string::npos, j.at("stopped").get<std::string>().find("--max-memory")) << f.out;
  // The limit is on the whole process (what it holds at the start counts)
  // and a growing table counts twice: tens of thousands of states, not more.
  EXPECT_GT(j.at("states").get<std::uint64_t>(), 10'000u);
  EXPECT_LT(j.at("states").get<std::uint64_t>(), 3'000'000u);
}

// Regression: a 200,000-place chain ended in `internal error:
// std::bad_alloc` (exit 70) after 13 GB; a 10,000-place one took 3.1 GB
// whatever --max-states said. (The figures of the 200,000-place chain are in
// docs/verification.md; a shorter chain keeps this test quick in debug.)
TEST(VerifyProcess, AChainMissionEndsWithinItsMemoryLimitEveryPropertyDecidedOrNot) {
  STRATA_SKIP_UNDER_TSAN();
  without_asan_quarantine();
  TempDir dir;
  constexpr std::size_t kPlaces = 20'000;
  const std::string mission = dir.file("chain.coral");
  {
    std::ofstream out(mission);
    out << "mission chain {\n  place p0 = 1";
    for (std::size_t i = 1; i < kPlaces; ++i) out << ", p" << i;
    out << ";\n";
    for (std::size_t i = 0; i + 1 < kPlaces; ++i)
      out << fmt::format("  transition t{} {{ wait {{ p{} }} signal {{ p{} }} }}\n", i, i, i + 1);
    out << "}\n";
  }
  Finished f = run_strata(
      dir, {"verify", mission, "--max-memory", std::to_string(200 + kSanitizerHeadroomMb), "--format", "json"},
      [](pid_t) {});
  ASSERT_TRUE(WIFEXITED(f.status)) << "ended by a signal: " << f.status;
  EXPECT_EQ(65, WEXITSTATUS(f.status)) << f.out.substr(0, 2000);
  auto j = json::parse(f.out, nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << f.out.substr(0, 2000);
  const json& net = j.at("nets").at(0);
  EXPECT_FALSE(net.at("complete").get<bool>());
  for (const json& p : net.at("properties")) EXPECT_NE("fails", p.at("status")) << p.dump();
  ASSERT_TRUE(net.at("invariants_complete").get<bool>());
  ASSERT_EQ(1u, net.at("invariants").size());
  EXPECT_EQ(kPlaces, net.at("invariants")[0].at("weights").size());
}

// Regression: an import of a FIFO blocked `check` and `verify` for ever.
TEST(VerifyProcess, AFifoImportIsRefusedAtOnceByCheckAndVerify) {
  TempDir dir;
  const auto fifo = core::testing::make_fifo("lib.coral");
  ASSERT_FALSE(fifo.empty());
  const std::string mission = dir.file("imports_fifo.coral");
  std::ofstream(mission) << fmt::format(
      "import \"{}\";\nmission m {{ place a = 1; exit e; transition t {{ wait {{ a }} signal {{ e }} }} }}\n",
      fifo.string());
  Finished check = run_strata(dir, {"check", "--format", "json", mission}, [](pid_t) {});
  ASSERT_TRUE(WIFEXITED(check.status));
  EXPECT_EQ(65, WEXITSTATUS(check.status)) << check.out;
  EXPECT_NE(std::string::npos, check.out.find("not a regular file")) << check.out;
  Finished verify = run_strata(dir, {"verify", "--format", "json", mission}, [](pid_t) {});
  ASSERT_TRUE(WIFEXITED(verify.status));
  EXPECT_EQ(65, WEXITSTATUS(verify.status)) << verify.out;
  auto j = json::parse(verify.out, nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << verify.out;
  EXPECT_EQ("FileUnreadable", j.at("diagnostics").at(0).at("kind")) << verify.out;
  EXPECT_EQ(1, j.at("diagnostics").at(0).at("line")) << verify.out;
  std::filesystem::remove_all(fifo.parent_path());
}

// A witness read from a FIFO (or any file that never ends) is refused at
// once, not waited for.
TEST(VerifyProcess, AFifoReplayFileIsRefusedAtOnce) {
  TempDir dir;
  const auto fifo = core::testing::make_fifo("witness.txt");
  ASSERT_FALSE(fifo.empty());
  const std::string net = std::string(STRATA_SOURCE_DIR) + "/tests/verify/mutex.pnml";
  const auto started = std::chrono::steady_clock::now();
  Finished f = run_strata(dir, {"verify", "--pnml", net, "--replay-file", fifo.string()}, [](pid_t) {});
  ASSERT_TRUE(WIFEXITED(f.status)) << "ended by a signal: " << f.status;
  EXPECT_EQ(74, WEXITSTATUS(f.status)) << f.out;
  EXPECT_LT(std::chrono::steady_clock::now() - started, std::chrono::seconds(10));
  std::filesystem::remove_all(fifo.parent_path());
}

}  // namespace
}  // namespace strata::cli::run_testing
