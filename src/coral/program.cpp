#include "coral/program.h"

#include <fmt/format.h>

#include "coral/lexer.h"
#include "petri/dump.h"

namespace strata::coral {

const CompiledNet* Program::find(std::string_view name) const {
  for (const auto& n : nets) {
    if (n.name == name) return &n;
  }
  return nullptr;
}

std::string_view tactic_type_name(ast::TacticType type) {
  switch (type) {
    case ast::TacticType::Exec: return "EXEC";
    case ast::TacticType::Ask: return "ASK";
    case ast::TacticType::Report: return "REPORT";
    case ast::TacticType::Ood: return "OOD";
  }
  return "?";
}

std::optional<ast::TacticType> parse_tactic_type(std::string_view text) {
  for (ast::TacticType t : core::kCallVerbs) {
    if (tactic_type_name(t) == text) return t;
  }
  return std::nullopt;
}

namespace {

std::string places(const petri::Net& net, const std::vector<petri::PlaceId>& ids) {
  std::string s;
  for (auto p : ids) {
    if (!s.empty()) s += ", ";
    s += net.place_name(p);
  }
  return s;
}

std::string describe(const petri::Net& net, const ActionSpec& a) {
  if (a.kind == ActionSpec::Kind::Phase) {
    return fmt::format("PHASE({}) -> [{}]", phase_call_text(a), places(net, a.outcomes));
  }
  std::string what;
  if (a.tactic == ast::TacticType::Report) {
    what = a.args.empty() ? escape(a.text) : a.args.front().text;
  } else {
    what = a.target;
    if (!a.args.empty()) {
      std::string args;
      for (const auto& l : a.args) args += (args.empty() ? "" : ", ") + l.text;
      what += "(" + args + ")";
    }
  }
  return fmt::format("TACTIC({}, {}) -> [{}]", tactic_type_name(a.tactic), what, places(net, a.outcomes));
}

}  // namespace

std::string phase_call_text(const ActionSpec& a) {
  if (a.args.empty()) return a.target;
  std::string args;
  for (const auto& l : a.args) args += (args.empty() ? "" : ", ") + l.text;
  return a.target + "(" + args + ")";
}

std::string net_head_text(const CompiledNet& n) {
  if (n.params.empty()) return n.name;
  std::string params;
  for (const auto& p : n.params) {
    params += (params.empty() ? "" : ", ") + (p.type == ast::ParamType::String ? "string " + p.name.text : p.name.text);
  }
  return n.name + "(" + params + ")";
}

std::string dump_net(const CompiledNet& n) {
  std::string out = fmt::format("{} {}\n", n.kind == ast::Net::Kind::Mission ? "mission" : "net", net_head_text(n));
  if (!n.data_file.empty()) out += fmt::format("data {}\n", escape(n.data_as_written));
  if (!n.exits.empty()) out += fmt::format("exits [{}]\n", places(n.net, n.exits));
  for (const auto& g : n.guards) {
    std::string terms;
    for (const auto& t : g.terms) terms += (terms.empty() ? "" : ", ") + t;
    out += fmt::format("guard {} every {} when {{{}}}\n", g.name, g.period, terms);
  }
  out += petri::dump_net(n.net);
  for (petri::TransitionId t = 0; t < n.net.transition_count(); ++t) {
    for (const auto& a : n.actions[t]) {
      out += fmt::format("action {}: {}\n", n.net.transition_name(t), describe(n.net, a));
    }
  }
  return out;
}

std::string dump_program(const Program& program) {
  std::string out;
  for (const auto& n : program.nets) {
    if (!out.empty()) out += '\n';
    out += dump_net(n);
  }
  return out;
}

}  // namespace strata::coral
