#include "coral/analysis.h"

#include <fmt/format.h>

#include "coral/guards.h"

namespace strata::coral {
namespace {

// The names of the outcomes of one action, in outcome order ("" = none).
std::vector<std::string> outcome_suffixes(const Program& program, const ActionSpec& a) {
  if (a.kind == ActionSpec::Kind::Phase) {
    std::vector<std::string> names;
    const CompiledNet* phase = program.find(a.target);
    for (std::size_t i = 0; i < a.outcomes.size(); ++i) {
      names.push_back(phase && i < phase->exits.size() ? std::string(phase->net.place_name(phase->exits[i]))
                                                       : fmt::format("exit{}", i + 1));
    }
    return names;
  }
  switch (a.tactic) {
    case ast::TacticType::Ask: return {"yes", "no"};
    case ast::TacticType::Exec:
    case ast::TacticType::Ood: return {"done"};
    default: return {};
  }
}

}  // namespace

std::string action_text(const ActionSpec& a) {
  if (a.kind == ActionSpec::Kind::Phase) return "PHASE " + phase_call_text(a);
  if (a.tactic == ast::TacticType::Report && !a.args.empty()) return "REPORT " + a.args.front().text;
  if (a.tactic == ast::TacticType::Report) {
    std::string text;
    for (char c : a.text) {
      if (c == '"' || c == '\\') text += '\\';
      text += c == '\n' ? std::string("\\n") : c == '\t' ? std::string("\\t") : std::string(1, c);
    }
    return fmt::format("REPORT \"{}\"", text);
  }
  std::string s = fmt::format("{} {}", tactic_type_name(a.tactic), a.target);
  if (!a.args.empty()) {
    s += '(';
    for (std::size_t i = 0; i < a.args.size(); ++i) s += (i ? ", " : "") + a.args[i].text;
    s += ')';
  }
  return s;
}

std::string answer_text(const Program& program, const ActionSpec& a, std::size_t answer) {
  if (a.kind == ActionSpec::Kind::Phase) return outcome_suffixes(program, a).at(answer);
  return a.tactic == ast::TacticType::Ask && answer == 1 ? "0" : "1";
}

AnalysisNet build_analysis_net(const Program& program, const CompiledNet& cn,
                               const std::vector<PhaseExits>& phase_exits) {
  AnalysisNet an;
  an.source = &cn;
  an.exits = cn.exits;
  const petri::Net& net = cn.net;
  petri::NetBuilder b;

  for (petri::PlaceId p = 0; p < net.place_count(); ++p) {
    b.add_place(net.place_name(p), net.initial_marking()[p]);
    an.places.push_back({p, 0, 0});
  }
  for (petri::TransitionId t = 0; t < net.transition_count(); ++t) {
    b.add_transition(net.transition_name(t), net.priority(t));
    for (const petri::Arc& a : net.inputs(t)) b.add_input(t, a.node, a.weight);
    for (const petri::Arc& a : net.outputs(t)) b.add_output(t, a.node, a.weight);
    an.steps.push_back({AnalysisNet::Step::Kind::Transition, t, 0, 0});
  }

  struct Flight {
    petri::PlaceId place;
    std::string name;
    petri::TransitionId transition;
    std::size_t action;
  };
  std::vector<Flight> flights;
  for (petri::TransitionId t = 0; t < net.transition_count(); ++t) {
    const auto& actions = cn.actions[t];
    for (std::size_t i = 0; i < actions.size(); ++i) {
      const ActionSpec& a = actions[i];
      std::vector<std::string> suffixes = outcome_suffixes(program, a);
      if (a.kind != ActionSpec::Kind::Phase && suffixes.empty()) continue;  // REPORT
      // "read_setpoint.next_setpt_data", ".2" for the second of the same name.
      std::size_t same = 1;
      for (std::size_t j = 0; j < i; ++j) same += actions[j].target == a.target ? 1 : 0;
      std::string flight = fmt::format("{}.{}", net.transition_name(t), a.target);
      if (same > 1) flight += fmt::format(".{}", same);
      const petri::PlaceId in_flight = b.add_place(flight, 0);
      an.places.push_back({std::nullopt, t, i});
      flights.push_back({in_flight, flight, t, i});
      b.add_output(t, in_flight, 1);

      const PhaseExits* known = nullptr;
      if (a.kind == ActionSpec::Kind::Phase) {
        for (const PhaseExits& pe : phase_exits) known = pe.phase == a.target ? &pe : known;
      }
      for (std::size_t k = 0; k < suffixes.size() && k < a.outcomes.size(); ++k) {
        if (known && k < known->reachable.size() && !known->reachable[k]) continue;
        const petri::TransitionId o = b.add_transition(fmt::format("{}.{}", flight, suffixes[k]), 0);
        b.add_input(o, in_flight, 1);
        b.add_output(o, a.outcomes[k], 1);
        an.steps.push_back({AnalysisNet::Step::Kind::Outcome, t, i, k});
      }
    }
  }
  // What a guard's trip does beside its drops: it forgets the calls in flight.
  for (std::uint32_t g = 0; g < cn.guards.size(); ++g) {
    const CompiledGuard& guard = cn.guards[g];
    for (const Flight& f : flights) {
      const GuardNode node = cn.guard_node(f.transition);
      const bool own = node.guard == g && (node.role == GuardRole::Poll || node.role == GuardRole::Ask);
      if (own) continue;
      const petri::TransitionId d = b.add_transition(fmt::format("{}.drop.{}", guard.name, f.name), kGuardDropPriority);
      b.add_input(d, guard.cancel, 1);
      b.add_input(d, f.place, 1);
      b.add_output(d, guard.cancel, 1);
      an.steps.push_back({AnalysisNet::Step::Kind::Forget, f.transition, f.action, g});
    }
  }
  an.net = std::move(b).build();
  if (!cn.guards.empty()) {
    an.urgent.assign(an.net.transition_count(), false);
    for (petri::TransitionId t = 0; t < an.net.transition_count(); ++t) {
      const AnalysisNet::Step& st = an.steps[t];
      const GuardRole role = cn.guard_node(st.transition).role;
      an.urgent[t] = st.kind == AnalysisNet::Step::Kind::Forget ||
                     (st.kind == AnalysisNet::Step::Kind::Transition &&
                      (role == GuardRole::Trip || role == GuardRole::Drop || role == GuardRole::Handle));
    }
  }
  return an;
}

bool AnalysisNet::guard_cycle(petri::TransitionId t) const {
  const Step& st = steps[t];
  if (st.kind == Step::Kind::Forget) return false;
  const GuardRole role = source->guard_node(st.transition).role;
  return role == GuardRole::Poll || role == GuardRole::Ask;
}

bool AnalysisNet::trips(petri::TransitionId t) const {
  const Step& st = steps[t];
  if (st.kind != Step::Kind::Outcome) return false;
  const GuardNode node = source->guard_node(st.transition);
  if (node.role != GuardRole::Ask) return false;
  return source->actions[st.transition][st.action].outcomes.at(st.answer) == source->guards[node.guard].loop.back();
}

}  // namespace strata::coral
