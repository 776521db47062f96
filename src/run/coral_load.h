#pragma once
// Loading a CORAL mission for a command: compile the file with its imports
// against the primitive catalogue, print every diagnostic (warnings too).
#include <optional>
#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

#include "coral/loader.h"
#include "coral/program.h"
#include "core/source.h"
#include "tactical/catalogue.h"
#include "tactical/execution_level.h"

namespace strata::run {

struct CoralLoad {
  core::SourceManager sources;
  std::optional<coral::Program> program;  // unset when it does not compile
  nlohmann::json diagnostics;             // every diagnostic, as `strata check --format json` prints them
  int exit_code = 0;                      // 65 invalid, 74 unreadable, else 0
};

// When it does not compile, a closing line: "COMMAND: PATH: 2 errorsSUFFIX".
// `files` reads the mission and its imports (null: the disk). `level`: the
// vehicle the mission is checked for (strategic::coral_check_options).
CoralLoad load_coral_file(const std::string& path, const tactical::Catalogue& catalogue, std::ostream& err,
                          std::string_view command, std::string_view suffix = "",
                          const coral::FileProvider* files = nullptr,
                          tactical::ExecutionLevel level = tactical::ExecutionLevel::Phoenix);

}  // namespace strata::run
