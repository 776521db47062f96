#pragma once
// The mission model of docs/studio.md: a .coral file compiled as `strata
// check` does, as JSON for the page (nets with their places, transitions,
// arcs and actions, each with its line; diagnostics).
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "coral/edit.h"
#include "coral/program.h"
#include "studio/sandbox.h"
#include "tactical/catalogue.h"

namespace strata::studio {

struct CompiledMission {
  nlohmann::json model;                   // the mission model
  std::optional<coral::Program> program;  // when it compiles
};

// Compiles `relative` (inside the sandbox) with its imports; `text`, when
// given, stands for that file's contents (an unsaved edit). The model's
// `text` is the text compiled, `layout` the layout file beside it (or null).
CompiledMission compile_mission(const Sandbox& sandbox, const std::string& relative,
                                const std::optional<std::string>& text, const tactical::Catalogue& catalogue);

// The nets of a program as the model's "nets" array; paths relative to the
// sandbox, `editable` for nets declared in `relative`.
nlohmann::json nets_json(const coral::Program& program, const core::SourceManager& sources, const Sandbox& sandbox,
                         const std::string& relative);

// An op of POST /api/edit (docs/studio.md) as a coral::Edit; the actions of
// set_actions become CORAL text. InvalidInput says what is wrong with it.
core::Result<coral::Edit> edit_from_json(const nlohmann::json& op);

// The catalogue for GET /api/primitives.
nlohmann::json primitives_json(const tactical::Catalogue& catalogue);

}  // namespace strata::studio
