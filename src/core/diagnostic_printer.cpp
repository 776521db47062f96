#include "core/diagnostic_printer.h"

#include <algorithm>
#include <string>

#include <fmt/format.h>

namespace strata::core {
namespace {

constexpr std::size_t kMaxShownLine = 200;

std::string printable(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    auto u = static_cast<unsigned char>(c);
    out.push_back((u >= 0x20 && u < 0x7f) || c == '\t' || u >= 0x80 ? c : '?');
  }
  return out;
}

// "file:line:col: " (no more than precision knows), or "TOOL: " for a
// problem that has no place in a file.
std::string location(const SourceManager& sources, SourceSpan span, Precision precision, std::string_view tool) {
  if (span.file >= sources.size()) return fmt::format("{}: ", tool);
  if (precision == Precision::File) return fmt::format("{}: ", sources.path(span.file));
  LineCol lc = sources.line_col(span.file, span.offset);
  if (precision == Precision::Line) return fmt::format("{}:{}: ", sources.path(span.file), lc.line);
  return fmt::format("{}:{}:{}: ", sources.path(span.file), lc.line, lc.col);
}

// The span's line with a caret under the span; a line without a column has
// no caret, a file without a line no excerpt.
void print_excerpt(std::ostream& out, const SourceManager& sources, SourceSpan span, Precision precision) {
  if (span.file >= sources.size() || precision == Precision::File) return;
  LineCol lc = sources.line_col(span.file, span.offset);
  std::string_view line = sources.line_text(span.file, lc.line);
  if (precision == Precision::Line) {
    if (line.size() > kMaxShownLine) line = line.substr(0, kMaxShownLine);
    out << "   " << printable(line) << "\n";
    return;
  }
  std::size_t col = lc.col - 1;
  if (col > line.size()) col = line.size();
  // Long lines: show a window around the column.
  std::size_t start = 0;
  if (line.size() > kMaxShownLine) {
    start = col > kMaxShownLine / 2 ? col - kMaxShownLine / 2 : 0;
    line = line.substr(start, kMaxShownLine);
  }
  std::size_t rel = col - start;
  std::size_t len =
      std::max<std::size_t>(1, std::min<std::size_t>(span.length, line.size() - std::min(rel, line.size())));
  std::string caret;
  for (std::size_t i = 0; i < rel && i < line.size(); ++i) caret.push_back(line[i] == '\t' ? '\t' : ' ');
  caret.push_back('^');
  caret.append(len - 1, '~');
  out << "   " << printable(line) << "\n   " << caret << "\n";
}

}  // namespace

void print_diagnostic(std::ostream& out, const SourceManager& sources, const Diagnostic& d, std::string_view tool) {
  out << location(sources, d.span, d.precision, tool) << severity_name(d.severity) << ": " << printable(d.message)
      << " [" << kind_name(d.kind) << "]\n";
  print_excerpt(out, sources, d.span, d.precision);
  for (const auto& note : d.notes) {
    out << location(sources, note.has_span ? note.span : d.span, note.has_span ? Precision::Span : d.precision, tool)
        << "note: " << printable(note.message) << "\n";
    if (note.has_span) print_excerpt(out, sources, note.span, Precision::Span);
  }
}

void print_diagnostics(std::ostream& out, const SourceManager& sources, std::span<const Diagnostic> diagnostics,
                       std::string_view tool) {
  for (const auto& d : diagnostics) print_diagnostic(out, sources, d, tool);
}

nlohmann::json diagnostics_to_json(const SourceManager& sources, std::span<const Diagnostic> diagnostics) {
  auto place = [&](nlohmann::json& j, SourceSpan span, Precision precision) {
    if (span.file >= sources.size()) return;
    j["file"] = sources.path(span.file);
    if (precision == Precision::File) return;
    LineCol b = sources.line_col(span.file, span.offset);
    LineCol e = sources.line_col(span.file, span.offset + span.length);
    j["line"] = b.line;
    if (precision == Precision::Line) return;
    j["col"] = b.col;
    j["end_line"] = e.line;
    j["end_col"] = e.col;
  };
  nlohmann::json arr = nlohmann::json::array();
  for (const auto& d : diagnostics) {
    nlohmann::json j;
    j["severity"] = severity_name(d.severity);
    j["kind"] = kind_name(d.kind);
    place(j, d.span, d.precision);
    j["message"] = d.message;
    j["notes"] = nlohmann::json::array();
    for (const auto& n : d.notes) {
      nlohmann::json nj;
      if (n.has_span) place(nj, n.span, Precision::Span);
      nj["message"] = n.message;
      j["notes"].push_back(std::move(nj));
    }
    arr.push_back(std::move(j));
  }
  return arr;
}

std::string dump_json(const nlohmann::json& j, int indent) {
  return j.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace strata::core
