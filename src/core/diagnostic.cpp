#include "core/diagnostic.h"

#include <algorithm>
#include <array>

namespace strata::core {
namespace {

struct KindInfo {
  std::string_view name;
  Severity severity;
  std::string_view description;
};

constexpr std::array kKinds = {
#define X(name, severity, description) KindInfo{#name, Severity::severity, description},
#include "core/diagnostic_kind.def"
#undef X
};

const KindInfo& info(DiagnosticKind kind) { return kKinds.at(static_cast<std::size_t>(kind)); }

}  // namespace

std::string_view kind_name(DiagnosticKind kind) { return info(kind).name; }
std::string_view kind_description(DiagnosticKind kind) { return info(kind).description; }
Severity default_severity(DiagnosticKind kind) { return info(kind).severity; }

std::string_view severity_name(Severity severity) {
  switch (severity) {
    case Severity::Note: return "note";
    case Severity::Warning: return "warning";
    case Severity::Error: return "error";
  }
  return "error";
}

std::vector<DiagnosticKind> all_kinds() {
  std::vector<DiagnosticKind> kinds;
  for (std::size_t i = 0; i < kKinds.size(); ++i) kinds.push_back(static_cast<DiagnosticKind>(i));
  return kinds;
}

Diagnostic* DiagnosticSink::report(DiagnosticKind kind, SourceSpan span, std::string message) {
  if (saturated_) return nullptr;
  Severity severity = default_severity(kind);
  if (severity == Severity::Error && errors_ >= max_errors_) {
    saturated_ = true;
    diagnostics_.push_back(
        {Severity::Error, DiagnosticKind::TooManyErrors, span, "too many errors; stopping here", {}, Precision::Span});
    ++errors_;
    return nullptr;
  }
  if (severity == Severity::Error) ++errors_;
  if (severity == Severity::Warning) ++warnings_;
  diagnostics_.push_back({severity, kind, span, std::move(message), {}, Precision::Span});
  return &diagnostics_.back();
}

void DiagnosticSink::sort() {
  std::stable_sort(diagnostics_.begin(), diagnostics_.end(), [](const Diagnostic& a, const Diagnostic& b) {
    if (a.kind == DiagnosticKind::TooManyErrors) return false;
    if (b.kind == DiagnosticKind::TooManyErrors) return true;
    if (a.span.file != b.span.file) return a.span.file < b.span.file;
    return a.span.offset < b.span.offset;
  });
}

void add_note(Diagnostic* d, std::string message) {
  if (d) d->notes.push_back({{}, false, std::move(message)});
}

void add_note(Diagnostic* d, SourceSpan span, std::string message) {
  if (d) d->notes.push_back({span, true, std::move(message)});
}

}  // namespace strata::core
