#include "core/file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <optional>
#include <random>

#include <fmt/format.h>

#include "core/unique_fd.h"

namespace strata::core {

Error errno_error(const std::string& what) {
  return make_error(ErrorCode::Io, fmt::format("{}: {}", what, std::strerror(errno)));
}

namespace {

// What fd really is, its links resolved; empty when that cannot be told (a
// name longer than the kernel gives, /proc not mounted).
std::string opened_name(int fd) {
  char buf[4096];
  const std::string link = fmt::format("/proc/self/fd/{}", fd);
  const ssize_t n = ::readlink(link.c_str(), buf, sizeof buf);
  if (n <= 0 || static_cast<std::size_t>(n) >= sizeof buf) return {};
  return std::string(buf, static_cast<std::size_t>(n));
}

Result<std::string> read_open_file(const std::string& path, std::size_t max_bytes, CannotOpenText cannot_open,
                                   std::string_view suffix);

}  // namespace

Result<std::string> read_regular_file(const std::string& path, std::size_t max_bytes, CannotOpenText cannot_open) {
  return read_open_file(path, max_bytes, cannot_open, {});
}

Result<std::string> read_regular_file_as_named(const std::string& path, std::size_t max_bytes, std::string_view suffix,
                                               CannotOpenText cannot_open) {
  return read_open_file(path, max_bytes, cannot_open,
                        std::string_view(path).ends_with(suffix) ? suffix : std::string_view());
}

namespace {

// suffix: not empty, the name the open file has must end in it.
Result<std::string> read_open_file(const std::string& path, std::size_t max_bytes, CannotOpenText cannot_open,
                                   std::string_view suffix) {
  // O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    const char* reason = std::strerror(errno);
    return make_error(ErrorCode::Io,
                      cannot_open ? cannot_open(path, reason) : fmt::format("cannot read '{}': {}", path, reason));
  }
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    return make_error(ErrorCode::Io, fmt::format("cannot read '{}': {}", path, std::strerror(errno)));
  }
  if (!S_ISREG(st.st_mode)) {
    return make_error(ErrorCode::Io, fmt::format("cannot read '{}': not a regular file", path));
  }
  if (!suffix.empty()) {
    const std::string real = opened_name(fd);
    if (real.empty()) {
      return make_error(ErrorCode::Io, fmt::format("'{}': where it leads cannot be told (a name too long to "
                                                   "resolve), so it cannot be shown to be a {} file; not read",
                                                   path, suffix));
    }
    if (!std::string_view(real).ends_with(suffix)) {
      return make_error(ErrorCode::Io,
                        fmt::format("'{}' is a link to '{}', which is not a {} file; not read", path, real, suffix));
    }
  }
  if (static_cast<std::size_t>(st.st_size) > max_bytes) {
    return make_error(ErrorCode::Overflow, fmt::format("'{}' is {} bytes, over the limit of {} bytes", path,
                                                       static_cast<long long>(st.st_size), max_bytes));
  }
  std::string text;
  // One byte past the size the file says it has: the read that finds the
  // end then needs no more room (growing by 64 KiB to find it zero-filled
  // 64 KiB for every file a run read: a sixth of a mission's load).
  text.resize(std::min(max_bytes, static_cast<std::size_t>(st.st_size)) + 1);
  std::size_t got = 0;
  // A file that grows while it is read is cut at max_bytes + 1, and refused.
  while (got <= max_bytes) {
    if (got == text.size()) text.resize(std::min(max_bytes + 1, text.size() + 65536));
    const ssize_t n = ::read(fd, text.data() + got, text.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return make_error(ErrorCode::Io, fmt::format("cannot read '{}': {}", path, std::strerror(errno)));
    if (n == 0) break;
    got += static_cast<std::size_t>(n);
  }
  if (got > max_bytes) {
    return make_error(ErrorCode::Overflow, fmt::format("'{}' is over the limit of {} bytes", path, max_bytes));
  }
  text.resize(got);
  return text;
}

}  // namespace

namespace {

using Fd = UniqueFd;

Error cannot_write(const std::string& shown, std::string_view why) {
  return make_error(ErrorCode::Io, fmt::format("cannot write '{}': {}", shown, why));
}

// Whether what is at `name` may be replaced: nothing there (st zeroed) or a
// regular file (st its status); otherwise the refusal. Never follows a link.
std::optional<Error> check_target(int dir_fd, const std::string& name, const std::string& shown, struct stat& st) {
  st = {};
  if (::fstatat(dir_fd, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0) {
    if (errno == ENOENT) {
      st = {};
      return std::nullopt;
    }
    return cannot_write(shown, std::strerror(errno));
  }
  if (S_ISREG(st.st_mode)) return std::nullopt;
  if (S_ISLNK(st.st_mode)) return cannot_write(shown, "a symbolic link; not written through it");
  if (S_ISDIR(st.st_mode)) return cannot_write(shown, "a folder");
  if (S_ISFIFO(st.st_mode)) return cannot_write(shown, "a FIFO, not a regular file; not replaced");
  return cannot_write(shown, "not a regular file; not replaced");
}

// A fresh hidden name beside `name` each time (the process, a counter and
// randomness), short enough for any name: NAME_MAX is 255 bytes.
std::string temp_name(const std::string& name) {
  static std::atomic<std::uint64_t> counter{0};
  thread_local std::mt19937_64 random{std::random_device{}()};
  return fmt::format(".{}.strata-tmp-{}-{}-{:08x}", name.substr(0, 120), ::getpid(), counter++, random() & 0xffffffffu);
}

}  // namespace

Result<void> write_file_atomically_at(int dir_fd, const std::string& name, std::string_view bytes,
                                      const std::string& shown, WriteOptions options) {
  assert(!name.empty() && name.find('/') == std::string::npos);
  struct stat before {};
  if (auto refused = check_target(dir_fd, name, shown, before)) return *refused;
  const bool existed = before.st_mode != 0;

  // A name already taken (by anything, a planted link included) makes
  // O_EXCL fail, and another name is tried.
  std::string temp;
  int fd = -1;
  for (int attempt = 0; attempt < 16 && fd < 0; ++attempt) {
    temp = temp_name(name);
    fd = ::openat(dir_fd, temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, options.mode);
    if (fd < 0 && errno != EEXIST) break;
  }
  if (fd < 0) return cannot_write(shown, std::strerror(errno));
  Fd out(fd);
  auto fail = [&](std::string_view why) {
    Error e = cannot_write(shown, why);
    ::unlinkat(dir_fd, temp.c_str(), 0);
    return e;
  };
  for (std::size_t done = 0; done < bytes.size();) {
    const ssize_t n = ::write(out.fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return fail(std::strerror(errno));
    done += static_cast<std::size_t>(n);
  }
  if (options.keep_existing_mode && existed && ::fchmod(out.fd, before.st_mode & 07777) != 0) {
    return fail(std::strerror(errno));
  }
  if (options.durable && ::fsync(out.fd) != 0) return fail(std::strerror(errno));
  const int closed = ::close(out.fd);
  out.fd = -1;
  if (closed != 0) return fail(std::strerror(errno));
  // Whatever took the target's place meanwhile is refused as before.
  struct stat now {};
  if (auto refused = check_target(dir_fd, name, shown, now)) {
    ::unlinkat(dir_fd, temp.c_str(), 0);
    return *refused;
  }
  if (::renameat(dir_fd, temp.c_str(), dir_fd, name.c_str()) != 0) return fail(std::strerror(errno));
  if (options.durable) ::fsync(dir_fd);  // the rename itself survives a crash (best effort: the file is in place)
  return {};
}

Result<void> write_file_atomically(const std::string& path, std::string_view bytes, WriteOptions options) {
  const std::filesystem::path p(path);
  const std::string name = p.filename().string();
  if (name.empty() || name == "." || name == "..") return cannot_write(path, "names a folder, not a file");
  const std::string folder = p.has_parent_path() ? p.parent_path().string() : ".";
  Fd dir(::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
  // A folder one may write in but not list: enough to write a file in (the
  // folder's own fsync then does nothing).
  if (dir.fd < 0 && errno == EACCES) dir.fd = ::open(folder.c_str(), O_PATH | O_DIRECTORY | O_CLOEXEC);
  if (dir.fd < 0) return cannot_write(path, std::strerror(errno));
  return write_file_atomically_at(dir.fd, name, bytes, path, options);
}

}  // namespace strata::core
