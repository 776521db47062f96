#include "studio/prolog_model.h"

#include <filesystem>
#include <vector>

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
  std::vector<strategic::PrologMessage> messages;
  const std::string absolute = (sandbox.root() / relative).string();
  const bool checked = PrologThread::instance().try_run([&] {
    auto loaded = strategic::PrologMission::load(absolute, catalogue, messages);
    if (!loaded && messages.empty()) messages.push_back({true, absolute, 0, 0, loaded.error().message, ""});
  });
  if (!checked) {
    model["check"] = "busy";
    return model;
  }
  for (const auto& m : messages) {
    json d = {{"severity", m.error ? "error" : "warning"},
              {"kind", m.kind.empty() ? std::string("Prolog") : m.kind},
              {"message", m.text},
              {"notes", json::array()}};
    if (!m.file.empty()) {
      d["file"] = sandbox.lexically_inside(m.file) ? sandbox.relative(fs::path(m.file).lexically_normal()) : m.file;
    }
    if (m.line > 0) {
      d["line"] = m.line;
      d["col"] = m.column;
    }
    model["diagnostics"].push_back(std::move(d));
  }
  return model;
}

}  // namespace strata::studio
