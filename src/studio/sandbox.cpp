#include "studio/sandbox.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "core/file.h"
#include "core/text.h"
#include "core/unique_fd.h"

namespace strata::studio {

namespace fs = std::filesystem;

Sandbox::Sandbox(const fs::path& root) : root_(fs::canonical(root)) {}

bool Sandbox::inside(const fs::path& real) const {
  auto r = root_.begin(), p = real.begin();
  for (; r != root_.end(); ++r, ++p) {
    if (p == real.end() || *p != *r) return false;
  }
  return true;
}

core::Result<fs::path> Sandbox::resolve(std::string_view rel, bool for_write) const {
  auto refuse = [&](std::string_view why) {
    return core::Error{core::ErrorCode::InvalidInput, fmt::format("'{}': {}", rel, why)};
  };
  if (rel.empty()) return refuse("no path given");
  if (rel.find('\0') != std::string_view::npos || rel.find('\\') != std::string_view::npos) {
    return refuse("not a plain relative path");
  }
  const fs::path p(rel);
  if (p.is_absolute()) return refuse("an absolute path; paths are relative to the studio's folder");
  for (const auto& part : p) {
    if (part == "..") return refuse("leaves the studio's folder");
  }
  std::error_code ec;
  const fs::path joined = root_ / p;
  if (for_write) {
    const fs::path folder = fs::canonical(joined.parent_path(), ec);
    if (ec) return refuse("its folder does not exist");
    if (!inside(folder)) return refuse("leaves the studio's folder");
    const fs::path target = folder / joined.filename();
    // A name the system cannot look up (too long, say) is refused here: the
    // callers' own lookups of it would throw.
    const fs::file_status status = fs::symlink_status(target, ec);
    if (status.type() == fs::file_type::none) return refuse(fmt::format("cannot be looked up ({})", ec.message()));
    // An existing link is followed: where it points must be inside too.
    if (fs::is_symlink(status)) {
      const fs::path real = fs::weakly_canonical(target, ec);
      if (ec || !inside(real)) return refuse("leaves the studio's folder");
      return real;
    }
    return target;
  }
  const fs::path real = fs::canonical(joined, ec);
  if (ec) return core::Error{core::ErrorCode::Io, fmt::format("'{}': no such file", rel)};
  if (!inside(real)) return refuse("leaves the studio's folder");
  return real;
}

namespace {

using Fd = core::UniqueFd;

// Where an open descriptor really is: the name may have been swapped for a
// link between the check and the open; the descriptor cannot be.
std::optional<fs::path> where_open(int fd) {
  std::error_code ec;
  fs::path p = fs::read_symlink(fmt::format("/proc/self/fd/{}", fd), ec);
  if (ec) return std::nullopt;
  return p;
}

core::Error disk_error(std::string_view what, std::string_view rel) {
  return core::Error{core::ErrorCode::Internal, fmt::format("cannot {} '{}': {}", what, rel, std::strerror(errno))};
}

}  // namespace

core::Result<std::string> Sandbox::read(std::string_view rel, std::size_t max_bytes) const {
  auto real = resolve(rel);
  if (!real) return real.error();
  return read_real(real.value(), rel, max_bytes);
}

bool Sandbox::lexically_inside(const fs::path& path) const {
  std::error_code ec;
  const fs::path absolute = fs::absolute(path, ec).lexically_normal();
  return !ec && inside(absolute);
}

core::Result<std::string> Sandbox::read_path(const fs::path& path, std::size_t max_bytes) const {
  const std::string shown = path.string();
  auto outside = [&] {
    return core::Error{core::ErrorCode::InvalidInput,
                       fmt::format("'{}' is outside the studio's folder; not read", shown)};
  };
  if (shown.find('\0') != std::string::npos) return outside();
  // Lexically first: a path that leaves the folder is never opened, nor
  // even looked at (whether it exists is none of the page's business).
  if (!lexically_inside(path)) return outside();
  std::error_code ec;
  const fs::path real = fs::canonical(fs::absolute(path, ec).lexically_normal(), ec);
  if (ec) return core::Error{core::ErrorCode::Io, fmt::format("'{}': no such file", shown)};
  if (!inside(real)) return outside();
  return read_real(real, shown, max_bytes);
}

core::Result<std::string> Sandbox::read_real(const fs::path& real, std::string_view shown,
                                             std::size_t max_bytes) const {
  // O_NONBLOCK: a FIFO planted under the name must not hang the worker.
  Fd f(::open(real.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK));
  if (f.fd < 0) {
    if (errno == ELOOP) {
      return core::Error{core::ErrorCode::InvalidInput, fmt::format("'{}' became a link; not read", shown)};
    }
    return core::Error{core::ErrorCode::Io, fmt::format("cannot open '{}': {}", shown, std::strerror(errno))};
  }
  struct stat st {};
  if (::fstat(f.fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    return core::Error{core::ErrorCode::InvalidInput, fmt::format("'{}' is not a regular file; not read", shown)};
  }
  if (auto at = where_open(f.fd); at && !inside(*at)) {
    return core::Error{core::ErrorCode::InvalidInput,
                       fmt::format("'{}' is outside the studio's folder; not read", shown)};
  }
  std::string out;
  char chunk[1 << 16];
  for (;;) {
    const ssize_t n = ::read(f.fd, chunk, sizeof chunk);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0)
      return core::Error{core::ErrorCode::Io, fmt::format("cannot read '{}': {}", shown, std::strerror(errno))};
    if (n == 0) break;
    out.append(chunk, static_cast<std::size_t>(n));
    if (out.size() > max_bytes) {
      return core::Error{core::ErrorCode::Overflow, fmt::format("'{}' is over {} bytes", shown, max_bytes)};
    }
  }
  return out;
}

core::Result<void> Sandbox::write(std::string_view rel, std::string_view bytes) const {
  auto resolved = resolve(rel, true);
  if (!resolved) return resolved.error();
  const fs::path target = resolved.value();  // a link inside: the file it points to
  const std::string name = target.filename().string();
  auto refuse = [&](std::string_view why) {
    return core::Error{core::ErrorCode::InvalidInput, fmt::format("'{}': {}", rel, why)};
  };
  // Everything below is relative to the folder's descriptor, itself checked
  // once open: a folder swapped for a link after resolve() is noticed.
  Fd dir(::open(target.parent_path().c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC));
  if (dir.fd < 0) return refuse("its folder cannot be opened");
  if (auto at = where_open(dir.fd); !at || !inside(*at)) return refuse("leaves the studio's folder");
  // The target, when there: a regular file (a link here now means it was
  // swapped after resolve(); a folder or a device is not a mission).
  auto check_target = [&](struct stat& st) -> std::optional<core::Error> {
    if (::fstatat(dir.fd, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0) {
      if (errno == ENOENT) return std::nullopt;
      return disk_error("look at", rel);
    }
    if (!S_ISREG(st.st_mode)) return refuse("is not a regular file; not written");
    return std::nullopt;
  };
  struct stat before {};
  if (auto e = check_target(before)) return *e;
  // Beneath these checks, the one atomic writer: a fresh temporary name
  // (a link planted at any name is never written through), fsync, rename
  // over the target; the file keeps its permissions (a script stays
  // executable, say).
  auto written = core::write_file_atomically_at(dir.fd, name, bytes, std::string(rel), {.keep_existing_mode = true});
  if (written) return written;
  // The target swapped for a link, a folder or a device meanwhile is a way
  // out like the others (403); anything else is the disk's refusal.
  struct stat now {};
  if (auto e = check_target(now)) return *e;
  return core::Error{core::ErrorCode::Internal, written.error().message};
}

core::Result<int> Sandbox::create_new(std::string_view folder, std::string_view name) const {
  auto refuse = [&](std::string_view why) {
    return core::Error{core::ErrorCode::InvalidInput, fmt::format("'{}/{}': {}", folder, name, why)};
  };
  if (name.empty() || name.find('/') != std::string_view::npos || name == "." || name == ".." ||
      name.find('\0') != std::string_view::npos) {
    return refuse("not a file name");
  }
  const fs::path f(folder);
  const std::string parent_rel = f.parent_path().generic_string();
  const std::string leaf = f.filename().string();
  if (!folder.empty() && (leaf.empty() || leaf == "." || leaf == "..")) return refuse("not a folder name");
  fs::path parent = root_;
  if (!parent_rel.empty()) {
    auto r = resolve(parent_rel);
    if (!r) return r.error();
    parent = r.value();
  }
  Fd up(::open(parent.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC));
  if (up.fd < 0) return refuse("its parent folder cannot be opened");
  if (auto at = where_open(up.fd); !at || !inside(*at)) return refuse("leaves the studio's folder");
  int dir_fd = -1;
  if (folder.empty()) {
    dir_fd = ::dup(up.fd);
  } else {
    if (::mkdirat(up.fd, leaf.c_str(), 0755) != 0 && errno != EEXIST) return disk_error("create the folder", folder);
    // O_NOFOLLOW: a link planted at the folder's name is refused, not used.
    dir_fd = ::openat(up.fd, leaf.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (dir_fd < 0) return refuse("is not a folder inside the studio's folder (a link?)");
  }
  Fd dir(dir_fd);
  if (dir.fd < 0) return disk_error("open the folder", folder);
  if (auto at = where_open(dir.fd); !at || !inside(*at)) return refuse("leaves the studio's folder");
  const std::string file(name);
  const int fd = ::openat(dir.fd, file.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) {
    if (errno == EEXIST) return core::Error{core::ErrorCode::Overflow, fmt::format("'{}/{}' exists", folder, name)};
    return disk_error("create", fmt::format("{}/{}", folder, name));
  }
  return fd;
}

core::Result<void> Sandbox::remove_empty(std::string_view folder, std::string_view name) const {
  auto real = resolve(folder.empty() ? std::string_view(".") : folder);
  if (!real) return real.error();
  Fd dir(::open(real.value().c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC));
  if (dir.fd < 0) return disk_error("open the folder", folder);
  if (auto at = where_open(dir.fd); !at || !inside(*at)) {
    return core::Error{core::ErrorCode::InvalidInput, fmt::format("'{}': leaves the studio's folder", folder)};
  }
  const std::string file(name);
  struct stat st {};
  if (::fstatat(dir.fd, file.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0) return disk_error("look at", name);
  if (!S_ISREG(st.st_mode) || st.st_size != 0) {
    return core::Error{core::ErrorCode::InvalidInput, fmt::format("'{}' is not an empty file; kept", name)};
  }
  if (::unlinkat(dir.fd, file.c_str(), 0) != 0) return disk_error("remove", name);
  return core::Result<void>();
}

std::string Sandbox::relative(const fs::path& path) const { return path.lexically_relative(root_).generic_string(); }

std::vector<std::string> Sandbox::list(const std::vector<std::string>& extensions, std::size_t* unnamed) const {
  std::vector<std::string> out;
  std::error_code ec;
  fs::recursive_directory_iterator it(root_, fs::directory_options::skip_permission_denied, ec), end;
  for (; !ec && it != end; it.increment(ec)) {
    const fs::path& p = it->path();
    const std::string name = p.filename().string();
    if (it->is_directory(ec)) {
      if (name == "build" || name == "node_modules" || name.starts_with('.') || it->is_symlink(ec)) {
        it.disable_recursion_pending();
      }
      continue;
    }
    if (!it->is_regular_file(ec)) continue;
    if (std::find(extensions.begin(), extensions.end(), p.extension().string()) == extensions.end()) continue;
    const fs::path real = fs::canonical(p, ec);
    if (ec || !inside(real)) continue;
    std::string rel = relative(p);
    // A name that is not UTF-8 cannot travel in JSON as itself: listed, it
    // came back mangled and could not be opened. Counted instead.
    if (!core::valid_utf8(rel)) {
      if (unnamed) ++*unnamed;
      continue;
    }
    out.push_back(std::move(rel));
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace strata::studio
