#include "studio/mission_model.h"

#include <algorithm>

#include <filesystem>
#include <map>
#include <fstream>
#include <sstream>

#include "coral/analysis.h"
#include "coral/compiler.h"
#include "coral/lexer.h"
#include "core/diagnostic_printer.h"

#include <fmt/format.h>

namespace strata::studio {
namespace {

namespace fs = std::filesystem;

// The disk, except one file whose text is given.
class OverlayProvider final : public coral::FileProvider {
 public:
  OverlayProvider(std::string path, std::string text) : path_(std::move(path)), text_(std::move(text)) {}
  std::string canonical(const std::string& path) const override { return disk_.canonical(path); }
  core::Result<std::string> read(const std::string& path) const override {
    if (disk_.canonical(path) == disk_.canonical(path_)) return text_;
    return disk_.read(path);
  }

 private:
  coral::DiskFileProvider disk_;
  std::string path_, text_;
};

nlohmann::json arcs_json(const petri::Net& net, std::span<const petri::Arc> arcs) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& a : arcs) out.push_back({{"place", net.place_name(a.node)}, {"weight", a.weight}});
  return out;
}

nlohmann::json action_json(const coral::CompiledNet& cn, const coral::ActionSpec& a) {
  nlohmann::json outcomes = nlohmann::json::array();
  for (auto p : a.outcomes) outcomes.push_back(cn.net.place_name(p));
  if (a.kind == coral::ActionSpec::Kind::Phase) {
    return {{"kind", "PHASE"}, {"target", a.target}, {"outcomes", outcomes}, {"label", coral::action_text(a)}};
  }
  nlohmann::json args = nlohmann::json::array();
  for (const auto& l : a.args) args.push_back(l.text);
  return {{"kind", "TACTIC"}, {"type", coral::tactic_type_name(a.tactic)}, {"target", a.target}, {"args", args},
          {"text", a.text}, {"outcomes", outcomes}, {"label", coral::action_text(a)}};
}

}  // namespace

nlohmann::json nets_json(const coral::Program& program, const core::SourceManager& sources, const Sandbox& sandbox,
                         const std::string& relative) {
  std::error_code ec;
  const fs::path own = fs::weakly_canonical(sandbox.root() / relative, ec);
  auto line_of = [&](const core::SourceSpan& span) {
    return span.file < sources.size() ? sources.line_col(span.file, span.offset).line : 0;
  };
  nlohmann::json nets = nlohmann::json::array();
  for (const auto& cn : program.nets) {
    const fs::path file = fs::weakly_canonical(cn.source_file, ec);
    nlohmann::json places = nlohmann::json::array(), transitions = nlohmann::json::array(), exits = nlohmann::json::array();
    std::vector<bool> is_exit(cn.net.place_count(), false);
    for (auto e : cn.exits) {
      is_exit[e] = true;
      exits.push_back(cn.net.place_name(e));
    }
    for (petri::PlaceId p = 0; p < cn.net.place_count(); ++p) {
      places.push_back({{"name", cn.net.place_name(p)}, {"initial", cn.net.initial_marking()[p]}, {"exit", static_cast<bool>(is_exit[p])},
                        {"line", p < cn.place_spans.size() ? line_of(cn.place_spans[p]) : 0}});
    }
    for (petri::TransitionId t = 0; t < cn.net.transition_count(); ++t) {
      nlohmann::json actions = nlohmann::json::array();
      for (const auto& a : cn.actions[t]) actions.push_back(action_json(cn, a));
      transitions.push_back({{"name", cn.net.transition_name(t)}, {"priority", cn.net.priority(t)},
                             {"line", t < cn.transition_spans.size() ? line_of(cn.transition_spans[t]) : 0},
                             {"inputs", arcs_json(cn.net, cn.net.inputs(t))}, {"outputs", arcs_json(cn.net, cn.net.outputs(t))},
                             {"actions", actions}});
    }
    nets.push_back({{"name", cn.name}, {"kind", cn.kind == coral::ast::Net::Kind::Mission ? "mission" : "phase"},
                    {"file", sandbox.relative(file)}, {"editable", file == own}, {"exits", exits},
                    {"places", places}, {"transitions", transitions}});
  }
  return nets;
}

CompiledMission compile_mission(const Sandbox& sandbox, const std::string& relative,
                                const std::optional<std::string>& text, const tactical::Catalogue& catalogue) {
  CompiledMission out;
  const std::string path = (sandbox.root() / relative).string();
  std::string source = text.value_or("");
  if (!text) {
    if (auto read = read_whole_file(path)) source = *read;
  }
  OverlayProvider files(path, source);
  core::SourceManager sources;
  core::DiagnosticSink sink;
  out.program = coral::compile_file(path, files, sources, sink, catalogue.check_options());
  sink.sort();
  nlohmann::json diagnostics = core::diagnostics_to_json(sources, sink.diagnostics());
  // Paths in diagnostics relative to the studio's folder, as everywhere else.
  for (auto& d : diagnostics) {
    if (d.contains("file") && d["file"].is_string()) {
      d["file"] = sandbox.relative(fs::weakly_canonical(d["file"].get<std::string>()));
    }
  }
  nlohmann::json layout = nullptr;
  if (auto l = read_whole_file(path + ".layout.json")) {
    layout = nlohmann::json::parse(*l, nullptr, false);
    if (layout.is_discarded()) layout = nullptr;
  }
  // The scenarios a run of it may name: scenarios/*.toml beside the mission.
  std::vector<std::string> scenarios;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(fs::path(path).parent_path() / "scenarios", ec)) {
    if (e.is_regular_file(ec) && e.path().extension() == ".toml") scenarios.push_back(e.path().stem().string());
  }
  std::sort(scenarios.begin(), scenarios.end());
  out.model = {{"path", relative}, {"text", source}, {"layout", layout}, {"diagnostics", diagnostics},
               {"nets", out.program ? nets_json(*out.program, sources, sandbox, relative) : nlohmann::json::array()},
               {"scenarios", scenarios}};
  return out;
}

namespace {

// One action of set_actions as CORAL text.
core::Result<std::string> action_text_of(const nlohmann::json& a) {
  auto names = [&](const char* key) {
    std::string out;
    for (const auto& n : a.value(key, nlohmann::json::array())) out += ", " + n.get<std::string>();
    return out;
  };
  const std::string kind = a.value("kind", "");
  const std::string target = a.value("target", "");
  if (kind == "PHASE") return fmt::format("PHASE({}{})", target, names("outcomes"));
  if (kind != "TACTIC") return core::Error{core::ErrorCode::InvalidInput, "an action's kind is TACTIC or PHASE"};
  const std::string type = a.value("type", "");
  if (type == "REPORT") return fmt::format("TACTIC(REPORT, {})", coral::escape(a.value("text", "")));
  if (type != "EXEC" && type != "ASK" && type != "OOD") {
    return core::Error{core::ErrorCode::InvalidInput, fmt::format("'{}' is not a TACTIC type", type)};
  }
  std::string call = target;
  const auto args = a.value("args", nlohmann::json::array());
  if (!args.empty()) {
    call += "(";
    for (std::size_t i = 0; i < args.size(); ++i) {
      const std::string arg = args[i].is_string() ? args[i].get<std::string>() : args[i].dump();
      call += (i ? ", " : "") + arg;
    }
    call += ")";
  }
  return fmt::format("TACTIC({}, {}{})", type, call, names("outcomes"));
}

}  // namespace

core::Result<coral::Edit> edit_from_json(const nlohmann::json& j) {
  using Op = coral::Edit::Op;
  static const std::map<std::string, Op, std::less<>> ops = {
      {"add_place", Op::AddPlace},           {"delete_place", Op::DeletePlace},
      {"rename_place", Op::RenamePlace},     {"set_initial", Op::SetInitial},
      {"add_transition", Op::AddTransition}, {"delete_transition", Op::DeleteTransition},
      {"rename_transition", Op::RenameTransition}, {"add_arc", Op::AddArc},
      {"delete_arc", Op::DeleteArc},         {"set_weight", Op::SetWeight},
      {"set_actions", Op::SetActions}};
  if (!j.is_object()) return core::Error{core::ErrorCode::InvalidInput, "op is not an object"};
  auto it = ops.find(j.value("op", ""));
  if (it == ops.end()) return core::Error{core::ErrorCode::InvalidInput, fmt::format("unknown op '{}'", j.value("op", ""))};
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

nlohmann::json primitives_json(const tactical::Catalogue& catalogue) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& p : catalogue.all()) {
    nlohmann::json args = nlohmann::json::array();
    for (const auto& a : p.args) {
      args.push_back({{"name", a.name}, {"type", a.type == tactical::Value::Type::Number ? "number" : "string"},
                      {"unit", a.unit}, {"min", a.min ? nlohmann::json(*a.min) : nlohmann::json(nullptr)},
                      {"max", a.max ? nlohmann::json(*a.max) : nlohmann::json(nullptr)}});
    }
    list.push_back({{"name", p.name}, {"kind", tactical::kind_name(p.kind)}, {"args", args}, {"doc", p.doc}});
  }
  return {{"primitives", list}};
}

}  // namespace strata::studio
