#pragma once
// Helpers for the coral unit tests: compile text held in memory and render
// diagnostics as "LINE:COL Kind" strings.
#include <string>
#include <vector>

#include "coral/compiler.h"
#include "core/diagnostic.h"

namespace strata::coral::testing {

struct Compiled {
  core::SourceManager sources;
  core::DiagnosticSink sink;
  std::optional<Program> program;

  // "3:5 UndefinedPlace" for each diagnostic, in report order (sorted).
  std::vector<std::string> kinds() const {
    std::vector<std::string> out;
    for (const auto& d : sink.diagnostics()) {
      std::string where = "?";
      if (d.span.file < sources.size()) {
        auto lc = sources.line_col(d.span.file, d.span.offset);
        where = std::to_string(lc.line) + ":" + std::to_string(lc.col);
      }
      out.push_back(where + " " + std::string(core::kind_name(d.kind)));
    }
    return out;
  }
};

// Compiles `main.coral` = text, with optional extra files for imports.
inline std::unique_ptr<Compiled> compile_text(const std::string& text,
                                              const std::vector<std::pair<std::string, std::string>>& extra = {},
                                              const CheckOptions& options = {}) {
  auto c = std::make_unique<Compiled>();
  MemoryFileProvider files;
  files.add("main.coral", text);
  for (const auto& [path, body] : extra) files.add(path, body);
  c->program = compile_file("main.coral", files, c->sources, c->sink, options);
  c->sink.sort();
  return c;
}

}  // namespace strata::coral::testing
