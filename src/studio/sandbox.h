#pragma once
// The studio's files: every path a request names is relative to one root
// folder, and must stay inside it. Refused (Error::InvalidInput, for a 403):
// an empty or absolute path, a backslash or NUL, a `..` component, and a
// path whose real location (symbolic links followed, for a file being
// written: its folder's) lies outside the root.
//
// Threads: immutable after construction; resolve() is safe from any thread.
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"

namespace strata::studio {

class Sandbox {
 public:
  // Precondition: root exists and is a folder.
  explicit Sandbox(const std::filesystem::path& root);

  const std::filesystem::path& root() const { return root_; }
  // The real path of `relative`. For reading it must exist; for writing its
  // folder must exist inside the root (the file itself may not exist yet).
  core::Result<std::filesystem::path> resolve(std::string_view relative, bool for_write = false) const;
  // `path` (inside the root) as a relative path with '/' separators.
  std::string relative(const std::filesystem::path& path) const;
  // Every regular file under the root with one of these extensions, as
  // relative paths, sorted; links that leave the root are not followed, and
  // folders named build, node_modules or starting with '.' are skipped.
  std::vector<std::string> list(const std::vector<std::string>& extensions) const;

 private:
  bool inside(const std::filesystem::path& real) const;
  std::filesystem::path root_;  // canonical
};

// The whole file, or nullopt when it cannot be read.
std::optional<std::string> read_whole_file(const std::filesystem::path& path);

}  // namespace strata::studio
