#include "campaign/output.h"

#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <regex>

#include <fmt/format.h>

#include "core/file.h"

namespace strata::campaign {
namespace {

namespace fs = std::filesystem;

}  // namespace

core::Result<void> make_real_dir(const std::string& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) == 0) {
    if (S_ISLNK(st.st_mode)) {
      return core::make_error(core::ErrorCode::Io, fmt::format("{}: a symbolic link; not writing through it", path));
    }
    if (!S_ISDIR(st.st_mode)) {
      return core::make_error(core::ErrorCode::Io, fmt::format("{}: exists and is not a folder", path));
    }
    return {};
  }
  if (::mkdir(path.c_str(), 0755) != 0) return core::errno_error(fmt::format("cannot create {}", path));
  return {};
}

namespace {

// Removes the earlier campaign's files in sub (case-N.ext), nothing else.
void clear_cases(const std::string& sub, const std::regex& name) {
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(sub, ec)) {
    if (e.is_regular_file(ec) && !e.is_symlink(ec) && std::regex_match(e.path().filename().string(), name)) {
      fs::remove(e.path(), ec);
    }
  }
}

}  // namespace

bool write_all_fd(int fd, const std::string& text) {
  // A write to a pipe whose reader is gone (a worker that died) raises
  // SIGPIPE, which ends a process that does not ignore it: strata's CLI
  // does, a program (or test) running a campaign need not. The signal is
  // the writing thread's own, so it is blocked for the write and, when the
  // write raised it, taken back before the mask is restored.
  sigset_t pipe_only, old;
  sigemptyset(&pipe_only);
  sigaddset(&pipe_only, SIGPIPE);
  ::pthread_sigmask(SIG_BLOCK, &pipe_only, &old);
  sigset_t pending;
  sigpending(&pending);
  const bool pending_before = sigismember(&pending, SIGPIPE) == 1;
  std::size_t done = 0;
  bool ok = true;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      ok = false;
      break;
    }
    done += static_cast<std::size_t>(n);
  }
  const int saved = errno;
  if (!ok && saved == EPIPE && !pending_before) {
    const timespec now{};
    while (::sigtimedwait(&pipe_only, nullptr, &now) < 0 && errno == EINTR) {}
  }
  ::pthread_sigmask(SIG_SETMASK, &old, nullptr);
  errno = saved;
  return ok;
}

core::Result<void> prepare_out_dir(const std::string& dir) {
  std::error_code ec;
  const bool existed = fs::exists(fs::symlink_status(dir, ec));
  if (auto r = make_real_dir(dir); !r) return r;
  if (existed && !fs::is_empty(dir, ec) && !fs::exists(fs::symlink_status(fs::path(dir) / "results.jsonl", ec))) {
    return core::make_error(core::ErrorCode::Io,
                            fmt::format("{}: a folder that is not empty and holds no results.jsonl; not writing "
                                        "a campaign into it",
                                        dir));
  }
  for (const char* sub : {"logs", "scenarios"}) {
    if (auto r = make_real_dir((fs::path(dir) / sub).string()); !r) return r;
  }
  clear_cases((fs::path(dir) / "logs").string(), std::regex(R"(case-\d+\.jsonl)"));
  clear_cases((fs::path(dir) / "scenarios").string(), std::regex(R"(case-\d+(\.params)?\.toml)"));
  for (const char* f : {"report.json", "report.html"}) {
    const fs::path p = fs::path(dir) / f;
    if (fs::is_regular_file(fs::symlink_status(p, ec))) fs::remove(p, ec);
  }
  return {};
}

core::Result<void> write_out_file(const std::string& dir, const std::string& name, const std::string& text,
                                  mode_t mode) {
  return core::write_file_atomically((fs::path(dir) / name).string(), text, {.mode = mode});
}

core::Result<ResultsFile> ResultsFile::create(const std::string& dir) {
  const std::string path = (fs::path(dir) / "results.jsonl").string();
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) return core::errno_error(fmt::format("cannot write {}", path));
  return ResultsFile(fd);
}

ResultsFile::~ResultsFile() {
  if (fd_ >= 0) ::close(fd_);
}

core::Result<void> ResultsFile::append(const nlohmann::ordered_json& line) {
  // One write per line: the file never holds half a line that a later
  // line's write could follow.
  if (!write_all_fd(fd_, line.dump() + "\n")) return core::errno_error("cannot write results.jsonl");
  return {};
}

}  // namespace strata::campaign
