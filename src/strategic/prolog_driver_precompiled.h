#pragma once
// Internal to strata_strategic: the precompiled PROLOG driver
// (docs/prolog.md §6), a quick-load file the build compiles from the
// driver's files and the libraries they use (prolog/precompile_driver.pl).
// ensure_driver() (prolog_driver.h) loads it instead of compiling the
// driver's text when it is the very file this build made: same SHA-256,
// same SWI-Prolog version. SWI-Prolog aborts the process on a truncated
// .qlf, so nothing else is ever given to it.
// Threads: the Prolog engine's thread only.
#include <filesystem>
#include <string>
#include <vector>

namespace strata::strategic::prolog_detail {

// Where the file is looked for, in order: $STRATA_PROLOG_DRIVER when set
// (alone; set to "" it turns the precompiled driver off), else beside the
// strata executable (a build folder), then in LIBDIR/strata relative to it
// (as cmake --install and the Debian package put it). Empty when turned off.
std::vector<std::filesystem::path> precompiled_driver_paths();

struct PrecompiledDriver {
  bool loaded = false;
  // Why it was not loaded, for a note: empty when it was, or when turned off.
  std::string note;
};

// Loads the precompiled driver into the started engine, or says why not
// before loading anything (a file missing, another build's, another
// SWI-Prolog's); then the caller loads the driver from its text. A load
// that starts and fails is reported too, and may have left part of it.
PrecompiledDriver load_precompiled_driver();

}  // namespace strata::strategic::prolog_detail
