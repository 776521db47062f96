#include "run/coral_load.h"

#include <algorithm>

#include <fmt/format.h>

#include "coral/compiler.h"
#include "core/diagnostic_printer.h"
#include "strategic/coral_catalogue.h"

namespace strata::run {

CoralLoad load_coral_file(const std::string& path, const tactical::Catalogue& catalogue,
                          const coral::FileProvider* files, tactical::ExecutionLevel level) {
  CoralLoad load;
  load.path = path;
  coral::DiskFileProvider disk;
  core::DiagnosticSink sink;
  load.program = coral::compile_file(path, files ? *files : disk, load.sources, sink,
                                     strategic::coral_check_options(catalogue, level));
  sink.sort();
  load.diagnostics = sink.diagnostics();
  load.errors = sink.error_count();
  // The mission file itself unreadable: its diagnostic names no loaded file.
  load.unreadable = std::any_of(load.diagnostics.begin(), load.diagnostics.end(), [&](const core::Diagnostic& d) {
    return d.kind == core::DiagnosticKind::FileUnreadable && d.span.file >= load.sources.size();
  });
  return load;
}

nlohmann::json CoralLoad::diagnostics_json() const { return core::diagnostics_to_json(sources, diagnostics); }

std::optional<Error> CoralLoad::error() const {
  if (program) return std::nullopt;
  Error e;
  e.kind = unreadable ? ErrorKind::Unreadable : ErrorKind::Invalid;
  e.message = fmt::format("{}: {} error{}", path, errors, errors == 1 ? "" : "s");
  for (const core::Diagnostic& d : diagnostics) {
    if (d.severity != core::Severity::Error || d.span.file >= sources.size()) continue;
    const core::LineCol at = sources.line_col(d.span.file, d.span.offset);
    e.place = Place{sources.path(d.span.file), at.line, at.col};
    break;
  }
  return e;
}

}  // namespace strata::run
