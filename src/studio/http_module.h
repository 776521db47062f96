#pragma once
// The studio's HTTP server (StudioServer, with cpp-httplib and through it
// OpenSSL, zlib and brotli) is built into a module of its own,
// libstrata_studio_http.so, which `strata studio` and `strata run --studio`
// load when they start serving. Every other command starts without those
// libraries: they were most of strata's start-up time (docs/architecture.md).
//
// The module resolves what it uses of Strata from the strata executable
// that loads it (built with its symbols exported), so one build's module
// only fits that build's strata: the entry point checks an ABI number and
// the size of StudioOptions, and a mismatch is an error, not a crash.
#include <filesystem>
#include <memory>
#include <vector>

#include "core/result.h"
#include "studio/studio_http.h"

namespace strata::studio {

inline constexpr const char* kHttpModuleFile = "libstrata_studio_http.so";
inline constexpr const char* kHttpModuleEntry = "strata_studio_http_server";
// Raise it when HttpServer, StudioOptions, RunLauncher or EventHub change.
inline constexpr int kHttpModuleAbi = 1;
// The entry point's type: null when abi or options_size is not the module's.
using HttpModuleEntry = HttpServer* (*)(int abi, std::size_t options_size, const StudioOptions& options, EventHub& hub);

// Where the module is looked for, in order: beside the strata executable
// (a build folder), then in the installed library folder relative to it
// (bin/../lib/strata/modules, as cmake --install and the Debian package put it).
std::vector<std::filesystem::path> http_module_paths();

// The studio's server, from the module (loaded once, and kept). An error
// names each place looked at, or what the loader said.
core::Result<std::unique_ptr<HttpServer>> make_http_server(const StudioOptions& options, EventHub& hub);

}  // namespace strata::studio
