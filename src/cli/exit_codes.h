#pragma once
// Exit codes of every strata command (style.md; sysexits-like).
namespace strata::cli {

enum ExitCode : int {
  kExitOk = 0,
  kExitAbort = 1,       // the mission ended in abort; `compare`: traces differ
  kExitUsage = 64,      // bad command line
  kExitInvalid = 65,    // invalid mission or input data
  kExitInternal = 70,   // a bug: an invariant broke
  kExitIo = 74,         // a file or the vehicle could not be reached
};

const char* exit_code_help();

}  // namespace strata::cli
