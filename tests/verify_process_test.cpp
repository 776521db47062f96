// `strata verify --pnml` as a process on a net too large to finish: Ctrl-C
// (SIGINT) and --max-memory both end it with a partial report and exit 1.
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "petri/net_families.h"
#include "petri/pnml.h"
#include "support/tank_run.h"

namespace strata::cli::run_testing {
namespace {

using namespace std::chrono_literals;

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

TEST(VerifyProcess, CtrlCEndsALongExplorationWithAPartialReport) {
  TempDir dir;
  const std::string net = write_big_net(dir);
  Finished f = run_strata(dir, {"verify", "--pnml", net}, [](pid_t pid) {
    std::this_thread::sleep_for(1500ms);
    kill(pid, SIGINT);
  });
  ASSERT_TRUE(WIFEXITED(f.status)) << "ended by a signal: " << f.status;
  EXPECT_EQ(1, WEXITSTATUS(f.status)) << f.out;
  EXPECT_NE(std::string::npos, f.out.find("PARTIAL: interrupted after ")) << f.out;
  EXPECT_NE(std::string::npos, f.out.find("  states ")) << f.out;
}

TEST(VerifyProcess, MaxMemoryEndsItWithAPartialReport) {
  TempDir dir;
  const std::string net = write_big_net(dir);
  Finished f = run_strata(dir, {"verify", "--pnml", net, "--max-memory", "16", "--format", "json"}, [](pid_t) {});
  ASSERT_TRUE(WIFEXITED(f.status)) << "ended by a signal: " << f.status;
  EXPECT_EQ(1, WEXITSTATUS(f.status)) << f.out;
  auto j = json::parse(f.out, nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << f.out;
  EXPECT_FALSE(j.at("complete").get<bool>());
  EXPECT_NE(std::string::npos, j.at("stopped").get<std::string>().find("--max-memory")) << f.out;
  EXPECT_GT(j.at("states").get<std::uint64_t>(), 100'000u);
  EXPECT_LT(j.at("states").get<std::uint64_t>(), 3'000'000u);
}

}  // namespace
}  // namespace strata::cli::run_testing
