#include "run/sonar_child.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "sonar/output.h"

extern char** environ;

namespace strata::run {

std::string self_executable() {
  char buf[4096];
  const ssize_t n = ::readlink("/proc/self/exe", buf, sizeof buf - 1);
  return n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : std::string("strata");
}

core::Result<SonarChild> SonarChild::start(const std::string& host, std::uint16_t port, const std::string& dir,
                                           const std::string& log_path, const std::vector<std::string>& extra) {
  std::vector<std::string> args = {self_executable(), "sonar", "--stream", host + ":" + std::to_string(port),
                                   "--out",           dir};
  args.insert(args.end(), extra.begin(), extra.end());
  std::vector<char*> argv;
  argv.reserve(args.size() + 1);
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  // The run blocks its stop signals for a watcher thread (cli/signal_watcher.h):
  // the manager starts with none blocked and none ignored, so SIGTERM ends it.
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  sigset_t none, stop;
  sigemptyset(&none);
  sigemptyset(&stop);
  for (int s : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) sigaddset(&stop, s);
  posix_spawnattr_setsigmask(&attr, &none);
  posix_spawnattr_setsigdefault(&attr, &stop);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
  pid_t pid = -1;
  const int rc = ::posix_spawn(&pid, argv[0], &actions, &attr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attr);
  if (rc != 0) {
    return core::Error{core::ErrorCode::Io, "cannot start the Sonar Manager (" + args[0] + "): " + std::strerror(rc)};
  }
  return SonarChild(pid);
}

SonarChild::~SonarChild() {
  if (pid_ > 0) stop(std::chrono::milliseconds(2000));
}

namespace {
int status_code(int status) {
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}
}  // namespace

std::optional<int> SonarChild::wait(std::chrono::milliseconds limit) {
  if (pid_ <= 0) return std::nullopt;
  const auto end = std::chrono::steady_clock::now() + limit;
  for (;;) {
    int status = 0;
    const pid_t r = ::waitpid(pid_, &status, WNOHANG);
    if (r == pid_) {
      pid_ = -1;
      return status_code(status);
    }
    if (r < 0 && errno != EINTR) {
      pid_ = -1;
      return -1;
    }
    if (std::chrono::steady_clock::now() >= end) return std::nullopt;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

int SonarChild::stop(std::chrono::milliseconds grace) {
  if (pid_ <= 0) return -1;
  const pid_t pid = pid_;
  ::kill(pid, SIGTERM);
  if (auto s = wait(grace)) return *s;
  ::kill(pid, SIGKILL);
  return wait(std::chrono::milliseconds(5000)).value_or(-1);
}

}  // namespace strata::run

namespace strata::run {

core::Result<SonarChild> start_sonar_manager(const std::string& dir, const std::string& host,
                                             std::optional<std::uint16_t> port, asio::io_context& io,
                                             const vehicle::SonarServer* sonar) {
  if (!port)
    return core::Error{core::ErrorCode::InvalidInput,
                       "the vehicle announced no sonar socket (no sonar= in its hello reply)"};
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return core::Error{core::ErrorCode::Io, "cannot create '" + dir + "': " + ec.message()};
  const std::size_t before = sonar ? sonar->readers() : 0;
  auto child = SonarChild::start(host, *port, dir, (std::filesystem::path(dir) / "manager.log").string());
  if (!child || !sonar) return child;
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (sonar->readers() <= before && std::chrono::steady_clock::now() < end) {
    if (auto gone = child.value().wait(std::chrono::milliseconds(0))) {
      return core::Error{core::ErrorCode::Io, "the Sonar Manager ended at once (exit " + std::to_string(*gone) +
                                                  "): see " + (std::filesystem::path(dir) / "manager.log").string()};
    }
    io.restart();
    io.run_for(std::chrono::milliseconds(5));
  }
  if (sonar->readers() <= before) {
    return core::Error{core::ErrorCode::Timeout, "the Sonar Manager did not connect within 10 s"};
  }
  return child;
}

void drain_sonar(asio::io_context& io, const vehicle::SonarServer* sonar) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (sonar && sonar->readers() > 0 && std::chrono::steady_clock::now() < end) {
    io.restart();
    io.run_for(std::chrono::milliseconds(5));
  }
}

std::string sonar_summary(const std::string& dir, std::optional<int> exit_status) {
  std::string what = !exit_status          ? std::string("the manager did not end")
                     : *exit_status == 0   ? std::string("the manager ended normally")
                     : *exit_status == 143 ? std::string("the manager was stopped after the run (exit 143)")
                                           : "the manager exited " + std::to_string(*exit_status);
  // The end summary, and the newest frame: the last scan.
  const sonar::LastLines last = sonar::read_last_lines(dir);
  const nlohmann::json end = nlohmann::json::parse(last.end, nullptr, false);
  const nlohmann::json frame = nlohmann::json::parse(last.frame, nullptr, false);
  if (end.is_object()) {
    what += fmt::format(", {} frames, {} pings, {} lost", end.value("frames", 0), end.value("pings", 0),
                        end.value("lost_pings", 0) + end.value("queue_drops", 0));
  }
  if (frame.is_object() && frame.contains("target") && frame["target"].is_object()) {
    const auto& t = frame["target"];
    what += fmt::format(", target at ({:.1f}, {:.1f}) m in the last scan", t.value("x_m", 0.0), t.value("y_m", 0.0));
  }
  return what + "; scans in " + dir;
}

}  // namespace strata::run
