#pragma once
// Problems in mission text are values, collected by a sink; parsing goes on
// after an error. Kinds are listed once, in diagnostic_kind.def.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "core/source.h"

namespace strata::core {

enum class Severity { Note, Warning, Error };

enum class DiagnosticKind {
#define X(name, severity, description) name,
#include "core/diagnostic_kind.def"
#undef X
};

std::string_view kind_name(DiagnosticKind kind);
std::string_view kind_description(DiagnosticKind kind);
Severity default_severity(DiagnosticKind kind);
std::string_view severity_name(Severity severity);
std::vector<DiagnosticKind> all_kinds();

struct DiagnosticNote {
  SourceSpan span;
  bool has_span = false;
  std::string message;
};

// How much of its span a diagnostic knows. CORAL's know all of it; a
// message of SWI-Prolog's may give a line without a column, or its file
// alone (the span's offset is then the line's start, or 0). The printers
// show no more than is known.
enum class Precision { Span, Line, File };

struct Diagnostic {
  Severity severity = Severity::Error;
  DiagnosticKind kind{};
  SourceSpan span;
  std::string message;
  std::vector<DiagnosticNote> notes;
  Precision precision = Precision::Span;
};

// Collects diagnostics up to a limit on errors; past it, one TooManyErrors
// diagnostic is recorded and further errors are dropped (warnings too).
class DiagnosticSink {
 public:
  static constexpr std::size_t kDefaultMaxErrors = 50;

  explicit DiagnosticSink(std::size_t max_errors = kDefaultMaxErrors) : max_errors_(max_errors) {}

  // Reports with the kind's default severity. Returns the stored diagnostic so
  // a caller can attach notes, or nullptr once the limit has been reached.
  Diagnostic* report(DiagnosticKind kind, SourceSpan span, std::string message);

  const std::vector<Diagnostic>& diagnostics() const { return diagnostics_; }
  std::size_t error_count() const { return errors_; }
  std::size_t warning_count() const { return warnings_; }
  bool has_errors() const { return errors_ > 0; }
  bool saturated() const { return saturated_; }

  // Orders diagnostics by file, then position, keeping report order on ties.
  void sort();

 private:
  std::size_t max_errors_;
  std::size_t errors_ = 0;
  std::size_t warnings_ = 0;
  bool saturated_ = false;
  std::vector<Diagnostic> diagnostics_;
};

// Adds a note to d if d is not null (the sink may have dropped it).
void add_note(Diagnostic* d, std::string message);
void add_note(Diagnostic* d, SourceSpan span, std::string message);

}  // namespace strata::core
