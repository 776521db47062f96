#include "studio/prolog_model.h"

#include <filesystem>
#include <vector>

#include "core/diagnostic_printer.h"
#include "strategic/prolog_mission.h"
#include "studio/mission_model.h"
#include "studio/prolog_thread.h"

namespace strata::studio {

namespace fs = std::filesystem;
using nlohmann::json;

json prolog_model(const Sandbox& sandbox, const tactical::Catalogue& catalogue, const std::string& relative,
                  std::string& etag) {
  json model = {{"path", relative},      {"kind", "prolog"},
                {"read_only", true},     {"text", ""},
                {"layout", nullptr},     {"layout_etag", nullptr},
                {"nets", json::array()}, {"diagnostics", json::array()},
                {"check", "done"},       {"scenarios", scenario_names(sandbox, relative)}};
  auto bytes = sandbox.read(relative);
  if (!bytes) {
    model["diagnostics"].push_back({{"severity", "error"},
                                    {"kind", "FileUnreadable"},
                                    {"file", relative},
                                    {"message", bytes.error().message},
                                    {"notes", json::array()}});
    model["check"] = "unreadable";
    return model;
  }
  etag = etag_of(bytes.value());
  model["text"] = bytes.value();
  model["etag"] = etag;
  // The rules checked as `strata check` does, on the process's PROLOG
  // thread; while a PROLOG run holds it, the text comes without a check.
  core::SourceManager sources;
  core::DiagnosticSink sink;
  const std::string absolute = (sandbox.root() / relative).string();
  const bool checked = PrologThread::instance().try_run([&] {
    auto loaded = strategic::PrologMission::load(absolute, catalogue, sources, sink);
    if (!loaded && !sink.has_errors()) {  // nothing reported: the driver could not start
      if (auto* d = sink.report(core::DiagnosticKind::PrologLoadError, {sources.add(absolute, ""), 0, 0},
                                loaded.error().message)) {
        d->precision = core::Precision::File;
      }
    }
  });
  if (!checked) {
    model["check"] = "busy";
    return model;
  }
  // As `strata check --format json` gives them, each file named inside the folder as the page names it.
  for (auto& d : core::diagnostics_to_json(sources, sink.diagnostics())) {
    if (d.contains("file")) {
      const std::string file = d["file"];
      if (sandbox.lexically_inside(file)) d["file"] = sandbox.relative(fs::path(file).lexically_normal());
    }
    model["diagnostics"].push_back(std::move(d));
  }
  return model;
}

}  // namespace strata::studio
