#pragma once
// The mission model of docs/studio.md: a .coral file compiled as `strata
// check` does, as JSON for the page (nets with their places, transitions,
// arcs and actions, each with its line; diagnostics).
#include <memory>
#include <optional>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "coral/edit.h"
#include "coral/program.h"
#include "core/source.h"
#include "studio/sandbox.h"
#include "tactical/catalogue.h"

namespace strata::studio {

struct CompiledMission {
  nlohmann::json model;                          // the mission model
  std::optional<coral::Program> program;         // when it compiles
  std::shared_ptr<core::SourceManager> sources;  // the text of the load (locations of the program's spans)
  std::string etag;                              // of the file as read from disk ("" when text was given or unreadable)
  bool escaped = false;                          // an import left the folder (refused, not read)
};

// The version of a file's bytes, as an HTTP entity tag (quotes included).
std::string etag_of(std::string_view bytes);

// "coral" for a .coral file, "prolog" for a .pl one, else empty: not a mission.
std::string mission_kind(const std::string& path);

// A scenario is a name: letters, digits, '_' and '-' (never a path).
bool plain_scenario_name(std::string_view name);
// The scenarios of `mission` (relative): scenarios/NAME.toml beside it,
// inside the root, as names, sorted; "nominal" always among them (the
// built-in nominal scenario when the mission has no nominal.toml).
std::vector<std::string> scenario_names(const Sandbox& sandbox, const std::string& mission);
// The file of scenario `name` of `mission`: InvalidInput for a name that is
// not plain or a file outside the root, Io when there is none.
core::Result<std::filesystem::path> scenario_file(const Sandbox& sandbox, const std::string& mission,
                                                  const std::string& name);

// Compiles `relative` (inside the sandbox) with its imports; `text`, when
// given, stands for that file's contents (an unsaved edit). The model's
// `text` is the text compiled, `layout` the layout file beside it (or null),
// `etag` and `layout_etag` their versions on disk. Every file is read
// through the sandbox: an import outside the folder is a diagnostic at the
// import, and is not read.
CompiledMission compile_mission(const Sandbox& sandbox, const std::string& relative,
                                const std::optional<std::string>& text, const tactical::Catalogue& catalogue);

// The nets of a program as the model's "nets" array; paths relative to the
// sandbox, `editable` for nets declared in `relative`.
nlohmann::json nets_json(const coral::Program& program, const core::SourceManager& sources, const Sandbox& sandbox,
                         const std::string& relative);

// An op of POST /api/edit (docs/studio.md) as a coral::Edit; the actions of
// set_actions become CORAL text. InvalidInput says what is wrong with it.
core::Result<coral::Edit> edit_from_json(const nlohmann::json& op);

// Why deleting a place or transition (op delete_place/delete_transition)
// is refused, or nullopt: a place that is an outcome of an action (a
// TACTIC's answer or a PHASE's exit mark: removing it from the list would
// change what the action means) or an exit of its net (each
// PHASE(net, ...) counts them). Nothing is refused when the text does not
// compile (program unset): use_left() then decides.
std::optional<std::string> refuse_delete(const std::optional<coral::Program>& program, const coral::Edit& edit);
// After a delete: an error diagnostic that names `name` and was not among
// `before` (a use the edit left behind), as the reason to refuse it.
std::optional<std::string> use_left(const nlohmann::json& before, const nlohmann::json& after, const std::string& name);

// The catalogue for GET /api/primitives.
nlohmann::json primitives_json(const tactical::Catalogue& catalogue);

}  // namespace strata::studio
