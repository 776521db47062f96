#include "coral/export.h"

#include <fmt/format.h>

#include "coral/analysis.h"
#include "petri/pnml.h"

namespace strata::coral {
namespace {

// A DOT string literal: quotes and backslashes escaped, newlines as \n.
std::string dot_quoted(std::string_view s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (c == '\n') {
      out += "\\n";
      continue;
    }
    out += c;
  }
  return out + '"';
}

}  // namespace

std::string export_pnml(const Program& program, const CompiledNet& net, const std::vector<PhaseExits>& phase_exits) {
  return petri::write_pnml(build_analysis_net(program, net, phase_exits).net, net.name);
}

std::string export_dot(const Program& program, const CompiledNet& cn, const std::vector<PhaseExits>& phase_exits) {
  const AnalysisNet an = build_analysis_net(program, cn, phase_exits);
  const petri::Net& net = an.net;
  std::vector<bool> is_exit(net.place_count(), false);
  for (petri::PlaceId e : cn.exits) is_exit[e] = true;

  std::string out =
      fmt::format("digraph {} {{\n  rankdir=TB;\n  node [fontname=\"Helvetica\", fontsize=10];\n", dot_quoted(cn.name));
  for (petri::PlaceId p = 0; p < net.place_count(); ++p) {
    const auto& origin = an.places[p];
    const petri::Tokens tokens = net.initial_marking()[p];
    std::string label(net.place_name(p));
    if (tokens > 0) label += tokens == 1 ? "\n●" : fmt::format("\n{} ●", tokens);
    if (origin.place) {
      out += fmt::format("  p{} [shape={}, label={}];\n", p, is_exit[p] ? "doublecircle" : "circle", dot_quoted(label));
    } else {
      const ActionSpec& a = cn.actions[origin.transition][origin.action];
      out += fmt::format("  p{} [shape=circle, style=dashed, label={}, tooltip={}];\n", p,
                         dot_quoted(fmt::format("{}\nin flight", action_text(a))), dot_quoted(label));
    }
  }
  for (petri::TransitionId t = 0; t < net.transition_count(); ++t) {
    const auto& step = an.steps[t];
    if (step.kind == AnalysisNet::Step::Kind::Transition) {
      std::string label(net.transition_name(t));
      if (net.priority(t) != 0) label += fmt::format(" (priority {})", net.priority(t));
      for (const ActionSpec& a : cn.actions[step.transition]) label += "\n" + action_text(a);
      out += fmt::format("  t{} [shape=box, style=filled, fillcolor=\"#dddddd\", label={}];\n", t, dot_quoted(label));
    } else if (step.kind == AnalysisNet::Step::Kind::Forget) {
      out += fmt::format("  t{} [shape=box, height=0.15, fontsize=8, label=\"forget\", tooltip={}];\n", t,
                         dot_quoted(net.transition_name(t)));
    } else {
      const ActionSpec& a = cn.actions[step.transition][step.action];
      out += fmt::format("  t{} [shape=box, height=0.15, fontsize=8, label={}, tooltip={}];\n", t,
                         dot_quoted(fmt::format("answers {}", answer_text(program, a, step.answer))),
                         dot_quoted(net.transition_name(t)));
    }
    for (const petri::Arc& arc : net.inputs(t)) {
      out += fmt::format("  p{} -> t{}{};\n", arc.node, t,
                         arc.weight == 1 ? "" : fmt::format(" [label=\"{}\"]", arc.weight));
    }
    for (const petri::Arc& arc : net.outputs(t)) {
      out += fmt::format("  t{} -> p{}{};\n", t, arc.node,
                         arc.weight == 1 ? "" : fmt::format(" [label=\"{}\"]", arc.weight));
    }
  }
  return out + "}\n";
}

}  // namespace strata::coral
