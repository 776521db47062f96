// libFuzzer target: any bytes as a PROLOG mission file, through the
// sandboxed load and the check (strategic::PrologMission::load, docs/prolog.md §4
// and §7), then, when the rules load, a bounded run of mission/0 against a
// scripted vehicle that answers every primitive call with 1. Must never
// crash, hang or run what the sandbox refuses. The file is written to a
// fresh folder of its own, beside a `marker`-free sibling: a side effect
// would show as a file there (checked: the target aborts).
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/diagnostic_printer.h"
#include "strategic/prolog_mission.h"
#include "tactical/catalogue.h"

namespace {

namespace fs = std::filesystem;
using namespace strata;

// Answers every call with 1; counts them.
class Vehicle : public strategic::PrologHost {
 public:
  void primitive(const std::string&, std::vector<tactical::Value>) override { ++calls; }
  std::optional<int> answer() override { return 1; }
  void report(const std::string&, std::vector<tactical::Value>) override {}
  void phase_started(const std::string&) override {}
  void phase_ended(const std::string&, const std::string&) override {}
  int calls = 0;
};

fs::path folder() {
  static const fs::path dir = [] {
    fs::path d = fs::temp_directory_path() / ("strata_prolog_fuzz_" + std::to_string(::getpid()));
    fs::create_directories(d / "mission");
    // A relative path in the rules (shell('touch marker')) lands there too.
    fs::current_path(d / "mission");
    return d;
  }();
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const fs::path file = folder() / "mission" / "fuzz.pl";
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  core::SourceManager sources;
  core::DiagnosticSink sink;
  strategic::LoadLimits limits;
  limits.time = std::chrono::milliseconds(2000);
  limits.inferences = 2'000'000;
  auto mission = strategic::PrologMission::load(file.string(), tactical::Catalogue::builtin(), sources, sink, limits);
  {
    // Both printers, on whatever places SWI-Prolog gave.
    std::ostringstream text;
    core::print_diagnostics(text, sources, sink.diagnostics());
    (void)core::dump_json(core::diagnostics_to_json(sources, sink.diagnostics()));
  }
  if (mission) {
    Vehicle vehicle;
    strategic::PrologMissionQuery query(*mission.value(), vehicle, 1'000'000);
    for (int step = 0; step < 64; ++step) {
      if (query.next() != prolog::Query::Status::Yield) break;
    }
    query.close();
  }
  // Anything the rules created beside themselves is a side effect the
  // sandbox let through.
  for (const auto& e : fs::directory_iterator(folder() / "mission")) {
    if (e.path().filename() != "fuzz.pl") std::abort();
  }
  return 0;
}
