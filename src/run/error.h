#pragma once
// Why a run could not start, as a value its caller switches on
// (docs/architecture.md, "One run, one safe end"). The run library never
// prints and never picks an exit code: the CLI maps a kind to its exit code
// and words it as `strata run: ...` (cli/run_errors.h); the studio and the
// campaign word it their own way.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "core/result.h"

namespace strata::run {

enum class ErrorKind {
  Usage,               // options that do not go together; a mission that is neither .coral nor .pl
  Unreadable,          // an input file could not be read (missing, not a regular file, no permission)
  Invalid,             // an input was read and is invalid: the mission, its data, scenario, parameters, answers
  FailsVerification,   // a CORAL mission fails verification and neither --unverified nor --answers was given
  LogUnwritable,       // the mission log could not be created, or a write to it failed
  VehicleUnavailable,  // the vehicle could not be started, reached, or did not answer hello
};
std::string_view to_string(ErrorKind kind);  // "usage", "unreadable", ...

// A place in an input file, when the problem has one.
struct Place {
  std::string file;
  std::uint32_t line = 0;    // 1-based; 0 unknown
  std::uint32_t column = 0;  // 1-based; 0 unknown
};

struct Error {
  ErrorKind kind = ErrorKind::Invalid;
  // The input concerned as the user named it ("--answers", "--vehicle",
  // "the mission log"), or "" when the message says it all.
  std::string input;
  std::string message;         // one line, for people, without a command's name
  std::optional<Place> place;  // where in the input, when known
};

// An input's load error as a run::Error: Io is Unreadable, anything else
// Invalid.
Error input_error(const core::Error& error, std::string input = {});

}  // namespace strata::run
