#pragma once
// Exit codes of every strata command and the outcome of a run (style.md;
// sysexits-like). The README lists them.
#include "core/result.h"

namespace strata {

enum ExitCode : int {
  kExitOk = 0,
  kExitAbort = 1,         // the mission did not complete (aborted, failed, halted, a limit); `compare`: traces differ
  kExitUsage = 64,        // bad command line
  kExitInvalid = 65,      // invalid mission or input data
  kExitUnavailable = 69,  // a service is missing or went away: gnuplot; the vehicle's sonar stream
  kExitInternal = 70,     // a bug: an invariant broke
  kExitIo = 74,           // a file or the vehicle could not be reached
  kExitSignalBase = 128,  // 128 + N: ended by signal N (SIGHUP 129, SIGINT 130, SIGTERM 143)
};

// The exit code for an input that could not be loaded: 74 when it could not
// be read (ErrorCode::Io), 65 when it was read and is invalid.
inline int exit_code_for_input(const core::Error& error) {
  return error.code == core::ErrorCode::Io ? kExitIo : kExitInvalid;
}

}  // namespace strata
