#pragma once
// TEST-ONLY: a FIFO with no writer, for the tests that a reader refuses what
// is not a regular file (opening one to read would block for ever).
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <string>

namespace strata::core::testing {

// A fresh FIFO called `name` in a folder of this process's own under the
// temporary directory; an empty path when it cannot be made. The caller
// removes its parent folder when done.
inline std::filesystem::path make_fifo(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("strata_fifo_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  auto path = dir / name;
  std::filesystem::remove(path);
  if (::mkfifo(path.c_str(), 0600) != 0) return {};
  return path;
}

}  // namespace strata::core::testing
