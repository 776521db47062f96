#include "cli/exit_codes.h"

namespace strata::cli {

const char* exit_code_help() {
  return "Exit codes: 0 ok (a run: the mission completed), 1 the mission did not complete (aborted, failed,\n"
         "halted, a limit reached), 64 usage, 65 invalid mission, 69 unavailable (gnuplot missing; strata sonar:\n"
         "the vehicle unreachable or gone), 70 internal error, 74 I/O error (a file or the vehicle cannot be\n"
         "reached), 128+N ended by signal N (129 SIGHUP, 130 SIGINT, 143 SIGTERM; a run surfaces first).";
}

}  // namespace strata::cli
