// `strata campaign` as a process: exit codes, and Ctrl-C (SIGINT) in the
// middle of a campaign keeping the finished cases.
#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "campaign/campaign_test_support.h"

namespace strata::campaign {
namespace {

using testing::TempDir;

// strata with args, stdout and stderr into files; returns its pid.
pid_t start(const std::vector<std::string>& args, const std::string& out, const std::string& err) {
  std::vector<std::string> argv{STRATA_BINARY};
  argv.insert(argv.end(), args.begin(), args.end());
  std::vector<char*> c;
  for (auto& a : argv) c.push_back(a.data());
  c.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    const int o = open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int e = open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(o, STDOUT_FILENO);
    dup2(e, STDERR_FILENO);
    execv(c[0], c.data());
    _exit(127);
  }
  return pid;
}

// The exit code, or -1 when it did not end within the bound (then killed).
int wait_exit(pid_t pid, std::chrono::seconds bound) {
  const auto deadline = std::chrono::steady_clock::now() + bound;
  int status = 0;
  while (std::chrono::steady_clock::now() < deadline) {
    if (waitpid(pid, &status, WNOHANG) == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  kill(pid, SIGKILL);
  waitpid(pid, &status, 0);
  return -1;
}

int run(const std::vector<std::string>& args, const TempDir& dir) {
  return wait_exit(start(args, dir.file("stdout"), dir.file("stderr")), std::chrono::seconds(120));
}

std::string spec(const std::string& nominal_max_depth_m, const std::string& leak_times) {
  return "missions = [\"" + testing::kTankDir +
         "/tank.coral\"]\n[expect.nominal]\nmax_depth_m = " + nominal_max_depth_m +
         "\n[[family]]\nfault = \"none\"\nexpect = \"nominal\"\n[[family]]\nfault = \"leak\"\n"
         "at_s = " +
         leak_times + "\n";
}

TEST(CampaignProcess, ExitsZeroWhenEveryCaseMeetsItsExpectationsAndOneWhenSomeDoNot) {
  TempDir dir;
  const std::string ok = dir.write("ok.toml", spec("1.8", "[4]"));
  EXPECT_EQ(0, run({"campaign", ok, "--out", dir.file("ok"), "-j", "2"}, dir));
  EXPECT_NE(std::string::npos, testing::read_text(dir.file("stdout")).find("2 of 2 cases ran, 2 passed, 0 failed"));

  const std::string bad = dir.write("bad.toml", spec("1.0", "[4]"));
  EXPECT_EQ(1, run({"campaign", bad, "--out", dir.file("bad"), "-j", "2"}, dir));
  EXPECT_NE(std::string::npos, testing::read_text(dir.file("stdout")).find("1 passed, 1 failed"));
  // The repro command, run, fails the same way alone.
  EXPECT_EQ(1, run({"campaign", bad, "--case", "0"}, dir));
  const std::string alone = testing::read_text(dir.file("stdout"));
  EXPECT_NE(std::string::npos, alone.find("FAIL max_depth_m")) << alone;
}

TEST(CampaignProcess, ASpecWithAnErrorExits65WithItsPlace) {
  TempDir dir;
  const std::string bad = dir.write("bad.toml", spec("1.8", "{ from = 0, to = 5, step = -1 }"));
  EXPECT_EQ(65, run({"campaign", bad, "--list"}, dir));
  EXPECT_NE(std::string::npos, testing::read_text(dir.file("stderr")).find(bad + ":9:35: 'at_s.step' must be"))
      << testing::read_text(dir.file("stderr"));
  EXPECT_EQ(74, run({"campaign", dir.file("none.toml"), "--list"}, dir));
}

TEST(CampaignProcess, SigintMidCampaignKeepsTheFinishedCasesAndExits130) {
  TempDir dir;
  // 301 cases: far more than run in the moment before the signal.
  const std::string s = dir.write("long.toml", spec("1.8", "{ from = 0, to = 30, step = 0.1 }"));
  const std::string results = dir.file("out/results.jsonl");
  const pid_t pid = start({"campaign", s, "--out", dir.file("out"), "-j", "2"}, dir.file("stdout"), dir.file("stderr"));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (testing::read_results(results).size() < 4 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_GE(testing::read_results(results).size(), 4u) << "no cases finished within 60 s";
  kill(pid, SIGINT);
  EXPECT_EQ(130, wait_exit(pid, std::chrono::seconds(30)));
  const auto lines = testing::read_results(results);
  EXPECT_GE(lines.size(), 4u);
  EXPECT_LT(lines.size(), 301u);
  std::set<std::uint64_t> indices;
  for (const auto& l : lines) {
    indices.insert(l["index"].get<std::uint64_t>());
    EXPECT_NE("crashed", l["outcome"]) << "a case stopped by Ctrl-C is not a crash: " << l.dump();
  }
  EXPECT_EQ(lines.size(), indices.size()) << "every case once";
  const auto report = nlohmann::json::parse(testing::read_text(dir.file("out/report.json")));
  EXPECT_TRUE(report["interrupted"].get<bool>());
  EXPECT_EQ(lines.size(), report["cases"]["done"].get<std::size_t>());
  EXPECT_NE(std::string::npos, testing::read_text(dir.file("stdout")).find("interrupted by SIGINT"));
}

}  // namespace
}  // namespace strata::campaign
