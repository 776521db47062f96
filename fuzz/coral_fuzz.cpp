// libFuzzer target: any bytes as a CORAL file, through lexer, parser,
// checker, compiler, both diagnostic printers, and a bounded run of each
// compiled net. Must never crash, hang or grow memory without bound.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "coral/compiler.h"
#include "core/diagnostic_printer.h"
#include "petri/state.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace strata;
  coral::MemoryFileProvider files;
  files.add("fuzz.coral", std::string(reinterpret_cast<const char*>(data), size));
  // An importable library file, so `import "lib.coral";` reaches real code.
  files.add("lib.coral",
            "net lib { place s = 1; exit ok, bad;\n"
            "  transition t { wait { s } action { TACTIC(ASK, q, ok, bad) } } }\n");
  core::SourceManager sources;
  core::DiagnosticSink sink;
  auto program = coral::compile_file("fuzz.coral", files, sources, sink);
  sink.sort();
  std::ostringstream sinkhole;
  core::print_diagnostics(sinkhole, sources, sink.diagnostics());
  sinkhole << core::dump_json(core::diagnostics_to_json(sources, sink.diagnostics()));
  if (program) {
    sinkhole << coral::dump_program(*program);
    for (const auto& n : program->nets) {
      petri::State state(n.net);
      for (int i = 0; i < 64; ++i) {
        auto t = state.enabled().first();
        if (!t || !state.fire(*t).ok()) break;
      }
    }
  }
  return 0;
}
