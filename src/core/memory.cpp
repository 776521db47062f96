#include "core/memory.h"

#include <unistd.h>

#include <cstdio>

namespace strata::core {

std::size_t resident_bytes() {
  std::FILE* f = std::fopen("/proc/self/statm", "r");
  if (!f) return 0;
  unsigned long size = 0, resident = 0;
  const int read = std::fscanf(f, "%lu %lu", &size, &resident);
  std::fclose(f);
  if (read != 2) return 0;
  const long page = ::sysconf(_SC_PAGESIZE);
  return static_cast<std::size_t>(resident) * static_cast<std::size_t>(page > 0 ? page : 4096);
}

std::size_t memory_left(std::size_t limit_bytes) {
  if (limit_bytes == 0) return 0;
  const std::size_t now = resident_bytes();
  return now < limit_bytes ? limit_bytes - now : 1;
}

}  // namespace strata::core
