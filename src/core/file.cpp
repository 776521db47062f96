#include "core/file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include <fmt/format.h>

namespace strata::core {

Error errno_error(const std::string& what) {
  return make_error(ErrorCode::Io, fmt::format("{}: {}", what, std::strerror(errno)));
}

Result<std::string> read_regular_file(const std::string& path, std::size_t max_bytes, CannotOpenText cannot_open) {
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
  if (static_cast<std::size_t>(st.st_size) > max_bytes) {
    return make_error(ErrorCode::Overflow, fmt::format("'{}' is {} bytes, over the limit of {} bytes", path,
                                                       static_cast<long long>(st.st_size), max_bytes));
  }
  std::string text;
  text.resize(static_cast<std::size_t>(st.st_size));
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

}  // namespace strata::core
