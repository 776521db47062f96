#include "cli/exit_codes.h"

namespace strata::cli {

const char* exit_code_help() {
  return "Exit codes: 0 ok, 1 mission ended in abort, 64 usage, 65 invalid mission,\n"
         "69 unavailable (gnuplot missing; strata sonar: the vehicle unreachable or gone), 70 internal error,\n"
         "74 I/O error (a file or the vehicle cannot be reached), 130/143 strata sonar stopped by SIGINT/SIGTERM.";
}

int exit_code_for_input(const core::Error& error) {
  return error.code == core::ErrorCode::Io ? kExitIo : kExitInvalid;
}

}  // namespace strata::cli
