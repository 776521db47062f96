#include "campaign/pool.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <deque>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "campaign/cases.h"
#include "campaign/output.h"

namespace strata::campaign {
namespace {

using Clock = std::chrono::steady_clock;

// A list handed to a worker at a time: small enough that the last cases
// spread over every worker, large enough that pipes are not the work.
constexpr std::size_t kMaxBatch = 32;
// After a first stop request, how long workers get to finish their case.
constexpr auto kStopGrace = std::chrono::seconds(5);

volatile std::sig_atomic_t g_worker_stop = 0;
extern "C" void on_worker_term(int) { g_worker_stop = 1; }

// The worker's life: read lists, run them, answer; exit on EOF or SIGTERM.
[[noreturn]] void worker_main(const Spec& spec, const CaseRunConfig& config, int cmd_fd, int res_fd) {
  struct sigaction sa {};
  sa.sa_handler = SIG_IGN;
  ::sigaction(SIGINT, &sa, nullptr);  // the terminal's Ctrl-C is the parent's to handle
  ::sigaction(SIGHUP, &sa, nullptr);
  sa.sa_handler = on_worker_term;
  ::sigaction(SIGTERM, &sa, nullptr);
  std::string buf;
  char chunk[4096];
  while (g_worker_stop == 0) {
    const auto nl = buf.find('\n');
    if (nl == std::string::npos) {
      const ssize_t n = ::read(cmd_fd, chunk, sizeof chunk);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) break;
      buf.append(chunk, static_cast<std::size_t>(n));
      continue;
    }
    const std::string line = buf.substr(0, nl);
    buf.erase(0, nl + 1);
    const char* p = line.c_str();
    while (*p != '\0' && g_worker_stop == 0) {
      char* end = nullptr;
      const std::uint64_t index = std::strtoull(p, &end, 10);
      if (end == p) break;
      p = end;
      const std::string started = fmt::format("S {}\n", index);
      if (!write_all_fd(res_fd, started)) ::_exit(2);
      CaseRunConfig case_config = config;
      // Run again for its log: its wall-clock limit starts again too.
      case_config.on_run_again = [&] {
        if (!write_all_fd(res_fd, started)) ::_exit(2);
      };
      const std::string result = run_case(spec, case_at(spec, index), case_config).dump();
      if (!write_all_fd(res_fd, "R " + result + "\n")) ::_exit(2);
    }
  }
  ::_exit(0);
}

std::string death_text(int status) {
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    return fmt::format("signal {} ({})", sig, ::strsignal(sig));
  }
  if (WIFEXITED(status)) return fmt::format("exit status {}", WEXITSTATUS(status));
  return "an unknown status";
}

struct Worker {
  pid_t pid = -1;
  int cmd_fd = -1;  // ours to write
  int res_fd = -1;  // ours to read
  std::string inbuf;
  std::deque<std::uint64_t> batch;       // handed over, no result yet
  std::optional<std::uint64_t> current;  // started, no result yet
  Clock::time_point started;
  std::string killed_why;  // set when we killed it
};

class Pool {
 public:
  Pool(const Spec& spec, const std::vector<std::uint64_t>& indices, const CaseRunConfig& config,
       const PoolOptions& options)
      : spec_(spec), config_(config), o_(options), queue_(indices.begin(), indices.end()) {}

  PoolOutcome run() {
    const int n = std::max(1, std::min<int>(o_.workers, static_cast<int>(queue_.size())));
    for (int i = 0; i < n && !queue_.empty(); ++i) spawn();
    auto last_tick = Clock::now();
    while (!workers_.empty()) {
      check_stop();
      std::vector<pollfd> fds;
      for (const Worker& w : workers_) fds.push_back({w.res_fd, POLLIN, 0});
      const int r = ::poll(fds.data(), fds.size(), 250);
      if (r < 0 && errno != EINTR) break;
      for (std::size_t i = fds.size(); i-- > 0;) {
        if (r > 0 && (fds[i].revents & (POLLIN | POLLHUP | POLLERR)) != 0) read_from(i);
      }
      check_time_limits();
      if (o_.on_tick && Clock::now() - last_tick > std::chrono::milliseconds(250)) {
        last_tick = Clock::now();
        o_.on_tick();
      }
    }
    return {done_, stopping_ && !queue_.empty()};
  }

 private:
  void spawn() {
    int cmd[2], res[2];
    if (::pipe2(cmd, O_CLOEXEC) != 0) return;
    if (::pipe2(res, O_CLOEXEC) != 0) {
      ::close(cmd[0]), ::close(cmd[1]);
      return;
    }
    const pid_t pid = ::fork();
    if (pid == 0) {
      for (const Worker& w : workers_) ::close(w.cmd_fd), ::close(w.res_fd);
      ::close(cmd[1]), ::close(res[0]);
      worker_main(spec_, config_, cmd[0], res[1]);
    }
    ::close(cmd[0]), ::close(res[1]);
    if (pid < 0) {
      ::close(cmd[1]), ::close(res[0]);
      return;
    }
    Worker w;
    w.pid = pid;
    w.cmd_fd = cmd[1];
    w.res_fd = res[0];
    workers_.push_back(std::move(w));
    feed(workers_.back());
  }

  // Hands the worker its next list, or closes its command pipe when there
  // is no more work (it exits).
  void feed(Worker& w) {
    if (!w.batch.empty() || w.cmd_fd < 0) return;
    if (queue_.empty() || stopping_) {
      ::close(w.cmd_fd);
      w.cmd_fd = -1;
      return;
    }
    const std::size_t share = queue_.size() / (workers_.size() * 4);
    const std::size_t n = std::clamp<std::size_t>(share, 1, kMaxBatch);
    std::string line;
    for (std::size_t i = 0; i < n && !queue_.empty(); ++i) {
      w.batch.push_back(queue_.front());
      line += fmt::format("{}{}", line.empty() ? "" : " ", queue_.front());
      queue_.pop_front();
    }
    if (!write_all_fd(w.cmd_fd, line + "\n")) {
      // It died already: its EOF will put the list back.
      ::close(w.cmd_fd);
      w.cmd_fd = -1;
    }
  }

  void read_from(std::size_t i) {
    Worker& w = workers_[i];
    char chunk[65536];
    const ssize_t n = ::read(w.res_fd, chunk, sizeof chunk);
    if (n < 0 && errno == EINTR) return;
    if (n <= 0) {
      reap(i);
      return;
    }
    w.inbuf.append(chunk, static_cast<std::size_t>(n));
    std::size_t nl;
    while ((nl = w.inbuf.find('\n')) != std::string::npos) {
      const std::string line = w.inbuf.substr(0, nl);
      w.inbuf.erase(0, nl + 1);
      if (line.starts_with("S ")) {
        w.current = std::strtoull(line.c_str() + 2, nullptr, 10);
        w.started = Clock::now();
      } else if (line.starts_with("R ")) {
        auto j = nlohmann::ordered_json::parse(line.substr(2), nullptr, false);
        if (j.is_discarded() || !j.contains("index")) continue;  // a worker's bug shows as a crashed case
        const std::uint64_t index = j["index"].get<std::uint64_t>();
        std::erase(w.batch, index);
        w.current.reset();
        deliver(j);
      }
    }
    feed(w);
  }

  // The worker's pipe ended: it exited or died. Its started case is lost.
  void reap(std::size_t i) {
    Worker w = std::move(workers_[i]);
    workers_.erase(workers_.begin() + static_cast<std::ptrdiff_t>(i));
    if (w.cmd_fd >= 0) ::close(w.cmd_fd);
    ::close(w.res_fd);
    int status = 0;
    while (::waitpid(w.pid, &status, 0) < 0 && errno == EINTR) {}
    const bool clean = WIFEXITED(status) && WEXITSTATUS(status) == 0 && w.batch.empty();
    if (clean) return;
    if (w.current && stopping_ && w.killed_why.empty()) {
      // Killed by the stop itself: the case did not run, it did not crash.
      w.current.reset();
    }
    if (w.current) {
      std::erase(w.batch, *w.current);
      const std::string why =
          !w.killed_why.empty() ? w.killed_why : fmt::format("the worker (pid {}) died: {}", w.pid, death_text(status));
      deliver(crashed_case(spec_, case_at(spec_, *w.current), why));
    }
    // The rest of its list goes back to the front of the queue.
    for (auto it = w.batch.rbegin(); it != w.batch.rend(); ++it) queue_.push_front(*it);
    if (!queue_.empty() && !stopping_) spawn();
  }

  void deliver(const nlohmann::ordered_json& j) {
    ++done_;
    if (o_.on_result) o_.on_result(j);
    if (o_.on_tick) o_.on_tick();
  }

  void check_time_limits() {
    const auto now = Clock::now();
    for (Worker& w : workers_) {
      if (!w.current || !w.killed_why.empty()) continue;
      if (std::chrono::duration<double>(now - w.started).count() > o_.case_wall_limit_s) {
        w.killed_why = fmt::format("over the limit of {} s of wall time for one case: its worker was killed",
                                   o_.case_wall_limit_s);
        ::kill(w.pid, SIGKILL);
      }
    }
    if (stopping_ && now > stop_deadline_) {
      for (Worker& w : workers_) ::kill(w.pid, SIGKILL);
    }
  }

  void check_stop() {
    const int requests = o_.stop_requests ? static_cast<int>(*o_.stop_requests) : 0;
    if (requests == 0 || requests == seen_requests_) return;
    seen_requests_ = requests;
    if (!stopping_) {
      stopping_ = true;
      stop_deadline_ = Clock::now() + kStopGrace;
      for (Worker& w : workers_) {
        if (w.cmd_fd >= 0) ::close(w.cmd_fd);
        w.cmd_fd = -1;
        ::kill(w.pid, SIGTERM);
      }
    }
    if (requests >= 2) {
      for (Worker& w : workers_) ::kill(w.pid, SIGKILL);
    }
  }

  const Spec& spec_;
  const CaseRunConfig& config_;
  const PoolOptions& o_;
  std::deque<std::uint64_t> queue_;
  std::vector<Worker> workers_;
  std::uint64_t done_ = 0;
  bool stopping_ = false;
  int seen_requests_ = 0;
  Clock::time_point stop_deadline_;
};

}  // namespace

PoolOutcome run_pool(const Spec& spec, const std::vector<std::uint64_t>& indices, const CaseRunConfig& config,
                     const PoolOptions& options) {
  return Pool(spec, indices, config, options).run();
}

PoolOutcome run_inline(const Spec& spec, const std::vector<std::uint64_t>& indices, const CaseRunConfig& config,
                       const PoolOptions& options) {
  PoolOutcome out;
  for (std::uint64_t index : indices) {
    if (options.stop_requests && *options.stop_requests != 0) {
      out.stopped = true;
      break;
    }
    const auto j = run_case(spec, case_at(spec, index), config);
    ++out.done;
    if (options.on_result) options.on_result(j);
    if (options.on_tick) options.on_tick();
  }
  return out;
}

}  // namespace strata::campaign
