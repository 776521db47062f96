#pragma once
// Reading a whole input file that someone else may have made: only a
// regular file is read (a FIFO, a device or a folder is refused at once,
// never waited on), and only up to a size the caller sets. Every input file
// outside the studio is read through here (CORAL sources, PROLOG rules,
// PNML, TOML, mission logs, gnuplot's messages, the files a run hashes).
#include <cstddef>
#include <string>

#include "core/result.h"

namespace strata::core {

// The message for a file that cannot be opened, from its path and the
// system's reason (strerror): for callers whose wording is known to their
// users ("cannot open 'x': ..."). By default: "cannot read 'x': reason".
using CannotOpenText = std::string (*)(const std::string& path, const char* reason);

// The bytes of the regular file at path, following links. Errors: Io when
// it cannot be opened or read, or is not a regular file; Overflow when it
// is larger than max_bytes (the message names the limit).
Result<std::string> read_regular_file(const std::string& path, std::size_t max_bytes,
                                      CannotOpenText cannot_open = nullptr);

// An Io error for the system call that just failed: "what: strerror(errno)".
Error errno_error(const std::string& what);

}  // namespace strata::core
