#pragma once
// Exit codes of every strata command: core/exit_codes.h, plus the help text.
#include "core/exit_codes.h"

namespace strata::cli {

const char* exit_code_help();

}  // namespace strata::cli
