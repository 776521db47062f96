#pragma once
// One printer for people, one JSON printer for tools and the studio.
#include <ostream>
#include <span>

#include <nlohmann/json.hpp>

#include "core/diagnostic.h"
#include "core/source.h"

namespace strata::core {

// file:line:col: severity: message [Kind], the source line, a caret under the
// span, then the notes. Bytes that are not printable are shown as '?'. A
// problem with no place in a file starts with `tool` instead: "strata
// check: error: cannot open ...".
void print_diagnostic(std::ostream& out, const SourceManager& sources, const Diagnostic& d,
                      std::string_view tool = "strata");
void print_diagnostics(std::ostream& out, const SourceManager& sources, std::span<const Diagnostic> diagnostics,
                       std::string_view tool = "strata");

// One object per diagnostic: severity, kind, file, line, col, end_line,
// end_col, message, notes[] (each with file/line/col when it has a span).
// The place has no more than the diagnostic knows (Precision): no col nor
// end_* without a column, no line without a line, no file without a file.
// docs/schema/check.schema.json describes it (`strata check --format json`).
nlohmann::json diagnostics_to_json(const SourceManager& sources, std::span<const Diagnostic> diagnostics);

// Serialises j; invalid UTF-8 from user input is replaced, never thrown on.
std::string dump_json(const nlohmann::json& j, int indent = 2);

}  // namespace strata::core
