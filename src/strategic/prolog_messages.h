#pragma once
// Inside the PROLOG mission driver: what SWI-Prolog printed while loading
// rules, and what the driver's checks found, as the driver collects them
// (a file, a line and a column, each perhaps unknown), and their report as
// core::Diagnostic values. Nothing outside src/strategic includes this:
// PrologMission::load reports core::Diagnostic values.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "core/diagnostic.h"
#include "core/source.h"

namespace strata::strategic {

struct PrologMessage {
  core::DiagnosticKind kind = core::DiagnosticKind::PrologLoadError;  // its default severity is the message's
  std::string file;                                                   // "" when nothing gave a place
  std::uint32_t line = 0;                                             // 0 when unknown
  std::uint32_t column = 0;                                           // 0 when unknown; from 1, in bytes
  std::string text;
};

bool is_error(const PrologMessage& message);

// Reports each message to sink, in order. Each file they name is added to
// sources once, with its text (read again, up to max_bytes) so the
// printers can show the line; the place keeps what the message knows
// (core::Precision): a message without a line, or in a file that cannot be
// read again, names its file alone.
void report_messages(std::span<const PrologMessage> messages, std::size_t max_bytes, core::SourceManager& sources,
                     core::DiagnosticSink& sink);

}  // namespace strata::strategic
