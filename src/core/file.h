#pragma once
// Reading a whole input file that someone else may have made: only a
// regular file is read (a FIFO, a device or a folder is refused at once,
// never waited on), and only up to a size the caller sets.
#include <cstddef>
#include <string>

#include "core/result.h"

namespace strata::core {

// The bytes of the regular file at path, following links. Errors: Io when
// it cannot be opened or read, or is not a regular file; Overflow when it
// is larger than max_bytes (the message names the limit).
Result<std::string> read_regular_file(const std::string& path, std::size_t max_bytes);

}  // namespace strata::core
