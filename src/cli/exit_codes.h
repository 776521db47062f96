#pragma once
// Exit codes of every strata command (style.md; sysexits-like).
#include "core/result.h"

namespace strata::cli {

enum ExitCode : int {
  kExitOk = 0,
  kExitAbort = 1,       // the mission ended in abort; `compare`: traces differ
  kExitUsage = 64,      // bad command line
  kExitInvalid = 65,    // invalid mission or input data
  kExitUnavailable = 69,  // a service is missing or went away: gnuplot; the vehicle's sonar stream
  kExitInternal = 70,   // a bug: an invariant broke
  kExitIo = 74,         // a file or the vehicle could not be reached
};

const char* exit_code_help();

// The exit code for an input that could not be loaded: 74 when it could not
// be read (ErrorCode::Io), 65 when it was read and is invalid.
int exit_code_for_input(const core::Error& error);

}  // namespace strata::cli
