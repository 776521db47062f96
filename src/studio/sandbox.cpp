#include "studio/sandbox.h"

#include <algorithm>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

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
    // An existing link is followed: where it points must be inside too.
    if (fs::is_symlink(fs::symlink_status(target, ec))) {
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

std::string Sandbox::relative(const fs::path& path) const { return path.lexically_relative(root_).generic_string(); }

std::vector<std::string> Sandbox::list(const std::vector<std::string>& extensions) const {
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
    out.push_back(relative(p));
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::optional<std::string> read_whole_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace strata::studio
