#pragma once
// What the commands ask of a mission file before they parse it, and the
// names an "unknown name" error lists.
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>

#include "core/mission_language.h"
#include "coral/program.h"

namespace strata::cli {

// Why `path` is not a mission file for a command that takes missions in
// the given languages: a wrong extension (a scenario, a log: a usage
// error, 64), or bytes that are not text (a NUL in its first 4 KB: a data
// error, 65, "PATH:LINE:COL: ..." at the first NUL). nullopt when it may
// be; a file that cannot be opened is left to the parser's own error.
struct NotAMission {
  std::string message;
  int exit_code = 64;
};
std::optional<NotAMission> not_a_mission(const std::string& path,
                                         std::initializer_list<core::MissionLanguage> languages);

// "tank, initialize, dive_from_surface": the program's nets, in order.
std::string net_names(const coral::Program& program);

}  // namespace strata::cli
