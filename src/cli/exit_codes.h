#pragma once
// Exit codes of every strata command: core/exit_codes.h, plus the help text.
#include <string_view>

#include "core/exit_codes.h"

namespace strata::cli {

const char* exit_code_help();

// The exit codes of one command whose own registration sets none (its
// --help footer), or nullptr.
const char* exit_codes_of(std::string_view command);

}  // namespace strata::cli
