#include "studio/http_module.h"

#include <dlfcn.h>

#include <mutex>
#include <string>
#include <system_error>

#include <fmt/format.h>

namespace strata::studio {
namespace {

namespace fs = std::filesystem;

#ifndef STRATA_STUDIO_MODULE_DIR
#define STRATA_STUDIO_MODULE_DIR "../lib/strata/modules"
#endif

struct Loaded {
  HttpModuleEntry entry = nullptr;
  std::string error;
};

Loaded load_module() {
  std::string looked;
  for (const fs::path& path : http_module_paths()) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) {
      looked += fmt::format("{}{}", looked.empty() ? "" : ", ", path.string());
      continue;
    }
    // RTLD_NOW: a symbol this strata lacks is an error here, not a crash
    // in the middle of a request.
    void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle)
      return {nullptr, fmt::format("cannot load the studio's HTTP module {}: {}", path.string(), ::dlerror())};
    auto entry = reinterpret_cast<HttpModuleEntry>(::dlsym(handle, kHttpModuleEntry));
    if (!entry) {
      return {nullptr, fmt::format("{} is not the studio's HTTP module (no {})", path.string(), kHttpModuleEntry)};
    }
    return {entry, {}};  // kept loaded: the server's code lives there
  }
  return {nullptr, fmt::format("the studio's HTTP module {} is missing (looked in {}): install strata whole",
                               kHttpModuleFile, looked)};
}

}  // namespace

std::vector<fs::path> http_module_paths() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  const fs::path dir = exe.parent_path();
  return {dir / kHttpModuleFile, (dir / STRATA_STUDIO_MODULE_DIR / kHttpModuleFile).lexically_normal()};
}

core::Result<std::unique_ptr<HttpServer>> make_http_server(const StudioOptions& options, EventHub& hub) {
  static std::once_flag once;
  static Loaded loaded;
  std::call_once(once, [] { loaded = load_module(); });
  if (!loaded.entry) return core::make_error(core::ErrorCode::Io, loaded.error);
  HttpServer* server = loaded.entry(kHttpModuleAbi, sizeof(StudioOptions), options, hub);
  if (!server) {
    return core::make_error(core::ErrorCode::Io,
                            "the studio's HTTP module is from another build of strata: install strata whole");
  }
  return std::unique_ptr<HttpServer>(server);
}

}  // namespace strata::studio
