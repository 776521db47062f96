#include "coral/compiler.h"

#include <filesystem>
#include <unordered_map>

namespace strata::coral {
namespace {

CompiledNet compile_net(const ast::Net& src, const LoadedFile& file) {
  CompiledNet out;
  out.name = src.name.text;
  out.kind = src.kind;
  out.params = src.params;
  out.source_file = file.path;
  out.span = src.span;
  if (!src.data.empty()) {
    std::filesystem::path dir = std::filesystem::path(file.path).parent_path();
    out.data_file = (dir / src.data.front().value).lexically_normal().string();
    out.data_as_written = src.data.front().value;
  }

  petri::NetBuilder b;
  for (const auto& p : src.places) {
    b.add_place(p.name.text, p.initial);
    out.place_spans.push_back(p.name.span);
  }
  for (const auto& t : src.transitions) {
    b.add_transition(t.name.text, t.priority);
    out.transition_spans.push_back(t.span);
  }
  // After a clean check every name is declared once, so at() cannot throw.
  std::unordered_map<std::string, petri::PlaceId> ids;
  for (petri::PlaceId i = 0; i < src.places.size(); ++i) ids.emplace(src.places[i].name.text, i);
  auto id = [&](const std::string& name) { return ids.at(name); };

  out.actions.resize(src.transitions.size());
  for (petri::TransitionId t = 0; t < src.transitions.size(); ++t) {
    const ast::Transition& tr = src.transitions[t];
    for (const auto& a : tr.waits) b.add_input(t, id(a.place.text), a.weight);
    for (const auto& a : tr.signals) b.add_output(t, id(a.place.text), a.weight);
    for (const auto& action : tr.actions) {
      ActionSpec spec;
      if (const auto* tactic = std::get_if<ast::Tactic>(&action)) {
        spec.kind = ActionSpec::Kind::Tactic;
        spec.tactic = *tactic->type;  // checked: no unknown type gets here
        if (tactic->function) {
          spec.target = tactic->function->name.text;
          spec.args = tactic->function->args;
        }
        if (tactic->text && tactic->text->kind == ast::Literal::Kind::Parameter) {
          spec.args = {*tactic->text};  // the engine substitutes the phase's value
        } else if (tactic->text) {
          spec.text = tactic->text->value;
        }
        for (const auto& p : tactic->places) spec.outcomes.push_back(id(p.text));
        spec.span = tactic->span;
      } else {
        const auto& phase = std::get<ast::Phase>(action);
        spec.kind = ActionSpec::Kind::Phase;
        spec.target = phase.phase.text;
        spec.args = phase.args;
        for (const auto& p : phase.places) spec.outcomes.push_back(id(p.text));
        spec.span = phase.span;
      }
      out.actions[t].push_back(std::move(spec));
    }
  }
  for (const auto& e : src.exits) out.exits.push_back(id(e.text));
  out.net = std::move(b).build();
  return out;
}

}  // namespace

std::optional<Program> compile(const Load& load, core::DiagnosticSink& sink, const CheckOptions& options) {
  check(load, sink, options);
  if (sink.has_errors()) return std::nullopt;
  Program program;
  for (const auto& file : load.files) {
    for (const auto& net : file.tree.nets) {
      if (net.kind == ast::Net::Kind::Mission) program.mission = program.nets.size();
      program.nets.push_back(compile_net(net, file));
    }
  }
  return program;
}

std::optional<Program> compile_file(const std::string& root, const FileProvider& provider, core::SourceManager& sources,
                                    core::DiagnosticSink& sink, const CheckOptions& options) {
  Load l = load(root, provider, sources, sink);
  // Syntax errors stop here: checking a partly parsed tree would report
  // names whose declarations failed to parse (cascades).
  if (sink.has_errors()) return std::nullopt;
  return compile(l, sink, options);
}

}  // namespace strata::coral
