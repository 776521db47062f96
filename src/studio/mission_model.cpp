#include "studio/mission_model.h"

#include <algorithm>
#include <cctype>

#include <filesystem>
#include <map>
#include <set>
#include <fstream>
#include <sstream>

#include "coral/analysis.h"
#include "coral/compiler.h"
#include "coral/lexer.h"
#include "coral/loader.h"
#include "core/diagnostic_printer.h"
#include "core/mission_language.h"
#include "run/scenario_folder.h"
#include "strategic/coral_catalogue.h"
#include "tactical/sha256.h"

#include <fmt/format.h>

namespace strata::studio {
namespace {

namespace fs = std::filesystem;

// The studio's folder, and nothing else: every file of a load (the
// mission, its imports) is read through the sandbox, so an import that
// leaves the folder (an absolute path, `..`, a link out) is a diagnostic at
// that import and its file is never opened. One file may stand for an
// unsaved text. The modules of the phase library (`import NAME;`) are not
// read through it: the loader reads those trusted Strata files itself,
// read-only (coral::Library), wherever the library is.
class SandboxProvider final : public coral::FileProvider {
 public:
  SandboxProvider(const Sandbox& sandbox, std::string path, std::optional<std::string> text)
      : sandbox_(sandbox), path_(std::move(path)), text_(std::move(text)) {}
  // A path that leaves the folder lexically is not looked at, not even to
  // resolve its links.
  std::string canonical(const std::string& path) const override {
    return sandbox_.lexically_inside(path) ? disk_.canonical(path) : fs::path(path).lexically_normal().string();
  }
  core::Result<std::string> read(const std::string& path) const override {
    if (text_ && canonical(path) == canonical(path_)) return *text_;
    auto r = sandbox_.read_path(path, coral::kMaxSourceSize);
    if (r) return r;
    // The loader's kinds: InvalidInput is a file too large, anything else a
    // file it cannot read (an escape among them).
    if (r.error().code == core::ErrorCode::InvalidInput) {
      // Refused: an escape, unless it is a FIFO, device or folder inside
      // the folder (not read either, but nothing left the folder).
      std::error_code ec;
      const bool not_a_file = sandbox_.lexically_inside(path) && !fs::is_symlink(path, ec) && fs::exists(path, ec) &&
                              !fs::is_regular_file(path, ec);
      if (!not_a_file) escaped_ = true;
      return core::Error{core::ErrorCode::Io, r.error().message};
    }
    if (r.error().code == core::ErrorCode::Overflow)
      return core::Error{core::ErrorCode::InvalidInput, r.error().message};
    return r;
  }
  bool escaped() const { return escaped_; }

 private:
  const Sandbox& sandbox_;
  coral::DiskFileProvider disk_;  // for canonical() only: it never reads here
  std::string path_;
  std::optional<std::string> text_;
  mutable bool escaped_ = false;  // one load, one thread
};

// A file of the load as the page shows it: relative to the studio's
// folder; a module of the phase library (docs/library.md), which the loader
// reads outside the folder and the studio never writes, by its own path.
std::string shown_file(const Sandbox& sandbox, const fs::path& file) {
  if (!sandbox.lexically_inside(file)) {
    std::error_code ec;
    for (const auto& dir : coral::library_dirs("coral")) {
      const fs::path rel = file.lexically_relative(fs::weakly_canonical(dir, ec));
      if (!rel.empty() && *rel.begin() != "..") return file.string();
    }
  }
  return sandbox.relative(file);
}

nlohmann::json arcs_json(const petri::Net& net, std::span<const petri::Arc> arcs) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& a : arcs) {
    nlohmann::json arc = nlohmann::json::object();
    arc["place"] = net.place_name(a.node);
    arc["weight"] = a.weight;
    out.push_back(std::move(arc));
  }
  return out;
}

nlohmann::json action_json(const coral::CompiledNet& cn, const coral::ActionSpec& a) {
  nlohmann::json outcomes = nlohmann::json::array();
  for (auto p : a.outcomes) outcomes.push_back(cn.net.place_name(p));
  nlohmann::json out = nlohmann::json::object();
  nlohmann::json args = nlohmann::json::array();
  for (const auto& l : a.args) args.push_back(l.text);
  if (a.kind == coral::ActionSpec::Kind::Phase) {
    out["kind"] = "PHASE";
    out["target"] = a.target;
    out["args"] = std::move(args);  // the phase's parameters as written: "100", "x1"
    out["outcomes"] = std::move(outcomes);
    out["label"] = coral::action_text(a);
    return out;
  }
  out["kind"] = "TACTIC";
  out["type"] = coral::tactic_type_name(a.tactic);
  out["target"] = a.target;
  out["args"] = std::move(args);
  out["text"] = a.text;
  out["outcomes"] = std::move(outcomes);
  out["label"] = coral::action_text(a);
  return out;
}

}  // namespace

nlohmann::json nets_json(const coral::Program& program, const core::SourceManager& sources, const Sandbox& sandbox,
                         const std::string& relative) {
  std::error_code ec;
  const fs::path own = fs::weakly_canonical(sandbox.root() / relative, ec);
  auto line_of = [&](const core::SourceSpan& span) {
    return span.file < sources.size() ? sources.line_col(span.file, span.offset).line : 0;
  };
  // Built by moves, not initializer lists: a list copies each member, and a
  // 5,000-transition net's arrays are megabytes.
  nlohmann::json nets = nlohmann::json::array();
  for (const auto& cn : program.nets) {
    const fs::path file = fs::weakly_canonical(cn.source_file, ec);
    nlohmann::json places = nlohmann::json::array(), transitions = nlohmann::json::array(),
                   exits = nlohmann::json::array();
    std::vector<bool> is_exit(cn.net.place_count(), false);
    for (auto e : cn.exits) {
      is_exit[e] = true;
      exits.push_back(cn.net.place_name(e));
    }
    for (petri::PlaceId p = 0; p < cn.net.place_count(); ++p) {
      nlohmann::json place = nlohmann::json::object();
      place["name"] = cn.net.place_name(p);
      place["initial"] = cn.net.initial_marking()[p];
      place["exit"] = static_cast<bool>(is_exit[p]);
      place["line"] = p < cn.place_spans.size() ? line_of(cn.place_spans[p]) : 0;
      places.push_back(std::move(place));
    }
    for (petri::TransitionId t = 0; t < cn.net.transition_count(); ++t) {
      nlohmann::json actions = nlohmann::json::array();
      for (const auto& a : cn.actions[t]) actions.push_back(action_json(cn, a));
      nlohmann::json tr = nlohmann::json::object();
      tr["name"] = cn.net.transition_name(t);
      tr["priority"] = cn.net.priority(t);
      tr["line"] = t < cn.transition_spans.size() ? line_of(cn.transition_spans[t]) : 0;
      tr["inputs"] = arcs_json(cn.net, cn.net.inputs(t));
      tr["outputs"] = arcs_json(cn.net, cn.net.outputs(t));
      tr["actions"] = std::move(actions);
      transitions.push_back(std::move(tr));
    }
    nlohmann::json net = nlohmann::json::object();
    net["name"] = cn.name;
    net["kind"] = cn.kind == coral::ast::Net::Kind::Mission ? "mission" : "phase";
    nlohmann::json params = nlohmann::json::array();
    for (const auto& p : cn.params) {
      params.push_back(
          {{"name", p.name.text}, {"type", p.type == coral::ast::ParamType::Number ? "number" : "string"}});
    }
    net["params"] = std::move(params);
    net["file"] = shown_file(sandbox, file);
    net["editable"] = file == own;
    net["exits"] = std::move(exits);
    net["places"] = std::move(places);
    net["transitions"] = std::move(transitions);
    nets.push_back(std::move(net));
  }
  return nets;
}

CompiledMission compile_mission(const Sandbox& sandbox, const std::string& relative,
                                const std::optional<std::string>& text, const tactical::Catalogue& catalogue) {
  CompiledMission out;
  const std::string path = (sandbox.root() / relative).string();
  std::optional<std::string> source = text;
  if (!source) {
    // Read once: the text shown, compiled and versioned are the same bytes.
    if (auto read = sandbox.read(relative, coral::kMaxSourceSize)) {
      source = std::move(read).value();
      out.etag = etag_of(*source);
    }
  }
  SandboxProvider files(sandbox, path, source);
  out.sources = std::make_shared<core::SourceManager>();
  core::SourceManager& sources = *out.sources;
  core::DiagnosticSink sink;
  out.program = coral::compile_file(path, files, sources, sink, strategic::coral_check_options(catalogue));
  out.escaped = files.escaped();
  sink.sort();
  nlohmann::json diagnostics = core::diagnostics_to_json(sources, sink.diagnostics());
  // Paths in diagnostics relative to the studio's folder, as everywhere else.
  for (auto& d : diagnostics) {
    if (d.contains("file") && d["file"].is_string()) {
      d["file"] = shown_file(sandbox, fs::weakly_canonical(d["file"].get<std::string>()));
    }
  }
  nlohmann::json layout = nullptr;
  nlohmann::json layout_etag = nullptr;
  if (auto l = sandbox.read(relative + ".layout.json")) {
    layout = nlohmann::json::parse(l.value(), nullptr, false);
    if (layout.is_discarded()) layout = nullptr;
    layout_etag = etag_of(l.value());
  }
  out.model = nlohmann::json::object();
  out.model["path"] = relative;
  out.model["text"] = source ? std::move(*source) : std::string();
  out.model["layout"] = std::move(layout);
  out.model["diagnostics"] = std::move(diagnostics);
  out.model["nets"] = out.program ? nets_json(*out.program, sources, sandbox, relative) : nlohmann::json::array();
  out.model["scenarios"] = scenario_names(sandbox, relative);
  if (!out.etag.empty()) out.model["etag"] = out.etag;
  out.model["layout_etag"] = layout_etag;
  return out;
}

std::string etag_of(std::string_view bytes) { return fmt::format("\"{}\"", tactical::sha256_hex(bytes).substr(0, 32)); }

std::string mission_kind(const std::string& path) {
  return std::string(core::language_key(core::mission_language(path)));
}

bool plain_scenario_name(std::string_view name) {
  if (name.empty() || name.size() > 64) return false;
  return std::all_of(name.begin(), name.end(),
                     [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-'; });
}

std::vector<std::string> scenario_names(const Sandbox& sandbox, const std::string& mission) {
  std::vector<std::string> names;
  auto folder = sandbox.resolve(run::scenarios_folder(mission).generic_string());
  if (!folder) return {"nominal"};  // none, or a link out: the built-in nominal only
  for (const std::string& name : run::scenario_names_in(folder.value())) {
    // Only what scenario_file() would give: a plain name, a file inside.
    if (plain_scenario_name(name) && scenario_file(sandbox, mission, name)) names.push_back(name);
  }
  // nominal is always there: the mission's nominal.toml, else the built-in
  // one (no faults).
  if (std::find(names.begin(), names.end(), "nominal") == names.end()) names.emplace_back("nominal");
  std::sort(names.begin(), names.end());
  return names;
}

core::Result<std::filesystem::path> scenario_file(const Sandbox& sandbox, const std::string& mission,
                                                  const std::string& name) {
  if (!plain_scenario_name(name)) {
    return core::Error{core::ErrorCode::InvalidInput,
                       fmt::format("'{}' is not a scenario name (letters, digits, '_' and '-', from the mission's "
                                   "scenarios/ folder)",
                                   name)};
  }
  const std::string rel = run::scenario_path(mission, name).generic_string();
  auto real = sandbox.resolve(rel);
  if (!real) {
    if (real.error().code == core::ErrorCode::Io) {
      return core::Error{core::ErrorCode::Io, fmt::format("no scenario '{}': there is no {}", name, rel)};
    }
    return core::Error{core::ErrorCode::InvalidInput,
                       fmt::format("scenario '{}': {} is outside the studio's folder", name, rel)};
  }
  std::error_code ec;
  if (!fs::is_regular_file(real.value(), ec)) {
    return core::Error{core::ErrorCode::InvalidInput, fmt::format("scenario '{}': {} is not a file", name, rel)};
  }
  return real;
}

namespace {

// One action of set_actions as CORAL text.
core::Result<std::string> action_text_of(const nlohmann::json& a) {
  auto names = [&](const char* key) {
    std::string out;
    for (const auto& n : a.value(key, nlohmann::json::array())) out += ", " + n.get<std::string>();
    return out;
  };
  // `f` or `f(1, "a", x)`: arguments as written (a JSON number as a number).
  auto call_of = [&](std::string call) {
    const auto args = a.value("args", nlohmann::json::array());
    if (args.empty()) return call;
    call += "(";
    for (std::size_t i = 0; i < args.size(); ++i) {
      const std::string arg = args[i].is_string() ? args[i].get<std::string>() : args[i].dump();
      call += (i ? ", " : "") + arg;
    }
    return call + ")";
  };
  const std::string kind = a.value("kind", "");
  const std::string target = a.value("target", "");
  if (kind == "PHASE") return fmt::format("PHASE({}{})", call_of(target), names("outcomes"));
  if (kind != "TACTIC") return core::Error{core::ErrorCode::InvalidInput, "an action's kind is TACTIC or PHASE"};
  const std::string type = a.value("type", "");
  if (type == "REPORT") {
    // A REPORT of a string parameter comes as args ["label"] and no text.
    const auto args = a.value("args", nlohmann::json::array());
    if (!args.empty() && args[0].is_string()) return fmt::format("TACTIC(REPORT, {})", args[0].get<std::string>());
    return fmt::format("TACTIC(REPORT, {})", coral::escape(a.value("text", "")));
  }
  if (type != "EXEC" && type != "ASK" && type != "OOD") {
    return core::Error{core::ErrorCode::InvalidInput, fmt::format("'{}' is not a TACTIC type", type)};
  }
  return fmt::format("TACTIC({}, {}{})", type, call_of(target), names("outcomes"));
}

}  // namespace

core::Result<coral::Edit> edit_from_json(const nlohmann::json& j) {
  using Op = coral::Edit::Op;
  static const std::map<std::string, Op, std::less<>> ops = {{"add_place", Op::AddPlace},
                                                             {"delete_place", Op::DeletePlace},
                                                             {"rename_place", Op::RenamePlace},
                                                             {"set_initial", Op::SetInitial},
                                                             {"add_transition", Op::AddTransition},
                                                             {"delete_transition", Op::DeleteTransition},
                                                             {"rename_transition", Op::RenameTransition},
                                                             {"add_arc", Op::AddArc},
                                                             {"delete_arc", Op::DeleteArc},
                                                             {"set_weight", Op::SetWeight},
                                                             {"set_actions", Op::SetActions}};
  if (!j.is_object()) return core::Error{core::ErrorCode::InvalidInput, "op is not an object"};
  auto it = ops.find(j.value("op", ""));
  if (it == ops.end())
    return core::Error{core::ErrorCode::InvalidInput, fmt::format("unknown op '{}'", j.value("op", ""))};
  try {
    coral::Edit e;
    e.op = it->second;
    e.net = j.value("net", "");
    e.name = it->second == Op::SetActions ? j.value("transition", "") : j.value("name", "");
    e.to = j.value("to", "");
    e.from = j.value("from", "");
    const std::int64_t value = j.value(e.op == Op::AddPlace || e.op == Op::SetInitial ? "initial" : "weight",
                                       std::int64_t{e.op == Op::AddArc ? 1 : 0});
    if (value < 0 || value > std::int64_t{0xffffffff}) {
      return core::Error{core::ErrorCode::InvalidInput, "a weight or marking is a whole number from 0 to 4294967295"};
    }
    e.value = static_cast<std::uint32_t>(value);
    for (const auto& a : j.value("actions", nlohmann::json::array())) {
      auto text = action_text_of(a);
      if (!text) return text.error();
      e.actions.push_back(text.value());
    }
    return e;
  } catch (const nlohmann::json::exception& ex) {
    return core::Error{core::ErrorCode::InvalidInput, fmt::format("op: {}", ex.what())};
  }
}

namespace {

// An action as written in CORAL: "PHASE(initialize, initialized, aborted)".
std::string action_source(const coral::CompiledNet& cn, const coral::ActionSpec& a) {
  std::string out;
  if (a.kind == coral::ActionSpec::Kind::Phase) {
    out = "PHASE(" + coral::phase_call_text(a);
  } else {
    out = fmt::format("TACTIC({}, {}", coral::tactic_type_name(a.tactic), a.target);
    if (!a.args.empty()) {
      out += "(";
      for (std::size_t i = 0; i < a.args.size(); ++i) out += (i ? ", " : "") + a.args[i].text;
      out += ")";
    }
  }
  for (auto p : a.outcomes) out += fmt::format(", {}", cn.net.place_name(p));
  return out + ")";
}

}  // namespace

std::optional<std::string> refuse_delete(const std::optional<coral::Program>& program, const coral::Edit& e) {
  if (!program || e.op != coral::Edit::Op::DeletePlace) return std::nullopt;
  for (const auto& cn : program->nets) {
    if (cn.name != e.net) continue;
    std::optional<petri::PlaceId> place;
    for (petri::PlaceId p = 0; p < cn.net.place_count(); ++p) {
      if (cn.net.place_name(p) == e.name) place = p;
    }
    if (!place) return std::nullopt;  // apply_edit says there is no such place
    for (auto x : cn.exits) {
      if (x == *place) {
        return fmt::format(
            "place '{}' is an exit of net '{}': every PHASE({}, ...) counts its exits; remove it from "
            "the `exit` list first (and from each PHASE that runs '{}')",
            e.name, e.net, e.net, e.net);
      }
    }
    for (petri::TransitionId t = 0; t < cn.net.transition_count(); ++t) {
      for (const auto& a : cn.actions[t]) {
        if (std::find(a.outcomes.begin(), a.outcomes.end(), *place) == a.outcomes.end()) continue;
        return fmt::format(
            "place '{}' is an outcome of {} in transition '{}': the action needs it; change or "
            "remove that action first",
            e.name, action_source(cn, a), cn.net.transition_name(t));
      }
    }
  }
  return std::nullopt;
}

std::optional<std::string> use_left(const nlohmann::json& before, const nlohmann::json& after,
                                    const std::string& name) {
  std::multiset<std::string> had;
  for (const auto& d : before) {
    if (d.value("severity", "") == "error") had.insert(d.value("message", ""));
  }
  const std::string quoted = "'" + name + "'";
  for (const auto& d : after) {
    if (d.value("severity", "") != "error") continue;
    const std::string message = d.value("message", "");
    if (auto it = had.find(message); it != had.end()) {
      had.erase(it);
      continue;
    }
    if (message.find(quoted) == std::string::npos) continue;
    return fmt::format("deleting '{}' would leave a use of it: line {}: {}", name, d.value("line", 0), message);
  }
  return std::nullopt;
}

nlohmann::json primitives_json(const tactical::Catalogue& catalogue) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& p : catalogue.all()) {
    nlohmann::json args = nlohmann::json::array();
    for (const auto& a : p.args) {
      args.push_back({{"name", a.name},
                      {"type", a.type == tactical::Value::Type::Number ? "number" : "string"},
                      {"unit", a.unit},
                      {"min", a.min ? nlohmann::json(*a.min) : nlohmann::json(nullptr)},
                      {"max", a.max ? nlohmann::json(*a.max) : nlohmann::json(nullptr)}});
    }
    list.push_back({{"name", p.name}, {"kind", core::call_verb_name(p.kind)}, {"args", args}, {"doc", p.doc}});
  }
  return {{"primitives", list}};
}

}  // namespace strata::studio
