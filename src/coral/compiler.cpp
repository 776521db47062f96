#include "coral/compiler.h"

#include <filesystem>
#include <set>
#include <unordered_map>

#include <fmt/format.h>

#include "coral/guards.h"

namespace strata::coral {
namespace {

// Which transitions and places of out each guard of src compiled to
// (guards.h names them "G.poll", "G.ask1", ...).
void describe_guards(const ast::Net& src, CompiledNet& out) {
  const petri::Net& net = out.net;
  out.guard_nodes.assign(net.transition_count(), GuardNode{});
  out.place_generated.assign(net.place_count(), false);
  for (petri::PlaceId p = 0; p < src.places.size(); ++p) out.place_generated[p] = src.places[p].generated;
  std::set<std::string> seen;
  for (const ast::Guard& g : src.guards) {
    if (!seen.insert(g.name.text).second) continue;
    const auto index = static_cast<std::uint32_t>(out.guards.size());
    CompiledGuard cg;
    cg.name = g.name.text;
    cg.period = g.period.text;
    cg.span = g.span;
    const std::string& G = g.name.text;
    auto transition = [&](const std::string& name, GuardRole role, std::uint32_t term = 0) {
      petri::TransitionId t = *net.find_transition(name);
      out.guard_nodes[t] = GuardNode{role, index, term};
      return t;
    };
    cg.poll = transition(G + ".poll", GuardRole::Poll);
    for (std::uint32_t k = 0; k < g.when.size(); ++k) {
      cg.terms.push_back(guard_term_text(g.when[k]));
      cg.asks.push_back(transition(fmt::format("{}.ask{}", G, k + 1), GuardRole::Ask, k));
    }
    cg.trip = transition(G + ".trip", GuardRole::Trip);
    cg.handle = transition(G + ".handle", GuardRole::Handle);
    cg.loop.push_back(*net.find_place(G + ".armed"));
    cg.loop.push_back(*net.find_place(G + ".due"));
    for (std::size_t k = 2; k <= g.when.size(); ++k) cg.loop.push_back(*net.find_place(fmt::format("{}.term{}", G, k)));
    cg.loop.push_back(*net.find_place(G + ".tripped"));
    cg.cancel = *net.find_place(G + ".cancel");
    for (const petri::Arc& a : net.readers(cg.cancel)) {
      if (net.priority(a.node) == kGuardDropPriority) out.guard_nodes[a.node] = GuardNode{GuardRole::Drop, index, 0};
    }
    out.guards.push_back(std::move(cg));
  }
}

CompiledNet compile_net(const ast::Net& src, const LoadedFile& file) {
  CompiledNet out;
  out.name = src.name.text;
  out.kind = src.kind;
  out.params = src.params;
  out.source_file = file.path;
  out.span = src.span;
  for (const auto& r : src.requirements) out.requirements.push_back({r.value, r.span});
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
  if (!src.guards.empty()) describe_guards(src, out);
  return out;
}

}  // namespace

std::optional<Program> compile(const Load& written, core::DiagnosticSink& sink, const CheckOptions& options) {
  // Guards become places and transitions of their nets before the check,
  // which then checks what they compile to like any transition.
  std::optional<Load> expanded;
  for (const auto& file : written.files) {
    for (const auto& net : file.tree.nets) {
      if (!net.guards.empty() && !expanded) expanded = written;
    }
  }
  if (expanded) {
    for (auto& file : expanded->files) {
      for (auto& net : file.tree.nets) expand_guards(net);
    }
  }
  const Load& load = expanded ? *expanded : written;
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
