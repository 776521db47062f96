#pragma once
// Loading a CORAL mission for a command: compile the file with its imports
// against the primitive catalogue. Nothing is printed: the diagnostics
// (warnings too) come back as values for the caller's printer.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "coral/loader.h"
#include "coral/program.h"
#include "core/diagnostic.h"
#include "core/source.h"
#include "run/error.h"
#include "tactical/catalogue.h"
#include "tactical/execution_level.h"

namespace strata::run {

struct CoralLoad {
  std::string path;
  core::SourceManager sources;
  std::optional<coral::Program> program;      // unset when it does not compile
  std::vector<core::Diagnostic> diagnostics;  // every one (warnings too), sorted by place
  std::size_t errors = 0;
  bool unreadable = false;  // the mission file itself could not be read

  // Every diagnostic, as `strata check --format json` prints them.
  nlohmann::json diagnostics_json() const;
  // Why it did not compile ("PATH: 2 errors"; Unreadable when the file
  // could not be read, else Invalid, placed at the first error); nullopt
  // when it compiled.
  std::optional<Error> error() const;
};

// `files` reads the mission and its imports (null: the disk). `level`: the
// vehicle the mission is checked for (strategic::coral_check_options).
CoralLoad load_coral_file(const std::string& path, const tactical::Catalogue& catalogue,
                          const coral::FileProvider* files = nullptr,
                          tactical::ExecutionLevel level = tactical::ExecutionLevel::Phoenix);

}  // namespace strata::run
