#include "strategic/prolog_driver_precompiled.h"

#include <cstdlib>
#include <system_error>

#include <fmt/format.h>

#include "prolog/engine.h"
#include "strategic/prolog_driver_precompiled_file.h"
#include "tactical/sha256.h"

namespace strata::strategic::prolog_detail {
namespace {

namespace fs = std::filesystem;

#ifndef STRATA_PRECOMPILED_DRIVER_DIR
#define STRATA_PRECOMPILED_DRIVER_DIR "../lib/strata"
#endif

constexpr std::size_t kMaxBytes = std::size_t{64} << 20;

// load_files(user:Path, [silent(true)]) for the text of path.
core::Result<bool> load_qlf(const std::string& path) {
  prolog::Frame frame;
  auto goal = prolog::parse_term("load_files(user:File, [silent(true)])");
  if (!goal) return goal.error();
  term_t spec = PL_new_term_ref();
  term_t file = PL_new_term_ref();
  if (!PL_get_arg(1, goal.value(), spec) || !PL_get_arg(2, spec, file) ||
      !PL_unify_chars(file, PL_ATOM | REP_UTF8, path.size(), path.c_str())) {
    return core::make_error(core::ErrorCode::Internal, "cannot build the precompiled driver's load goal");
  }
  return prolog::call_term(goal.value());
}

}  // namespace

std::vector<fs::path> precompiled_driver_paths() {
  const std::string name(kPrecompiledDriverFile);
  if (const char* env = std::getenv("STRATA_PROLOG_DRIVER")) {
    if (*env == '\0') return {};
    return {fs::path(env)};
  }
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  const fs::path dir = exe.parent_path();
  return {dir / name, (dir / STRATA_PRECOMPILED_DRIVER_DIR / name).lexically_normal()};
}

PrecompiledDriver load_precompiled_driver() {
  const auto paths = precompiled_driver_paths();
  if (paths.empty()) return {};
  std::string looked;
  for (const fs::path& path : paths) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) {
      looked += fmt::format("{}{}", looked.empty() ? "" : ", ", path.string());
      continue;
    }
    auto digest = tactical::sha256_file(path.string(), kMaxBytes);
    if (!digest) return {false, fmt::format("{} cannot be read: {}", path.string(), digest.error().message)};
    if (digest.value() != kPrecompiledDriverSha256) {
      return {false, fmt::format("{} is not the one this strata was built with (stale or corrupt)", path.string())};
    }
    const long version = static_cast<long>(PL_query(PL_QUERY_VERSION));
    if (version != kPrecompiledDriverSwiVersion) {
      return {false, fmt::format("{} was compiled by SWI-Prolog {}, and this is {}", path.string(),
                                 kPrecompiledDriverSwiVersion, version)};
    }
    auto loaded = load_qlf(path.string());
    if (!loaded || !loaded.value()) {
      return {false, fmt::format("{} did not load: {}", path.string(),
                                 loaded ? std::string("load_files/2 failed") : loaded.error().message)};
    }
    return {true, {}};
  }
  return {false, fmt::format("is missing (looked in {})", looked)};
}

}  // namespace strata::strategic::prolog_detail
