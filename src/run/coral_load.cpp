#include "run/coral_load.h"

#include <fmt/format.h>

#include "core/exit_codes.h"
#include "coral/compiler.h"
#include "core/diagnostic_printer.h"
#include "strategic/coral_catalogue.h"

namespace strata::run {

CoralLoad load_coral_file(const std::string& path, const tactical::Catalogue& catalogue, std::ostream& err,
                          std::string_view command, std::string_view suffix, const coral::FileProvider* files,
                          tactical::ExecutionLevel level) {
  CoralLoad load;
  coral::DiskFileProvider disk;
  core::DiagnosticSink sink;
  load.program = coral::compile_file(path, files ? *files : disk, load.sources, sink,
                                     strategic::coral_check_options(catalogue, level));
  sink.sort();
  load.diagnostics = core::diagnostics_to_json(load.sources, sink.diagnostics());
  bool unreadable_root = false;
  for (const auto& d : sink.diagnostics()) {
    core::print_diagnostic(err, load.sources, d);
    if (d.kind == core::DiagnosticKind::FileUnreadable && d.span.file >= load.sources.size()) {
      unreadable_root = true;
    }
  }
  if (!load.program) {
    err << fmt::format("{}: {}: {} error{}{}\n", command, path, sink.error_count(), sink.error_count() == 1 ? "" : "s",
                       suffix);
    load.exit_code = unreadable_root ? kExitIo : kExitInvalid;
  }
  return load;
}

}  // namespace strata::run
