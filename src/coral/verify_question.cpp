#include "coral/verify_question.h"

#include <fmt/format.h>

#include "coral/verifier_internal.h"

namespace strata::coral {

core::Result<AnalysisNet> question_analysis_net(const Program& program, std::string_view name,
                                                const petri::QuestionOptions& limits) {
  std::optional<std::size_t> root;
  for (std::size_t i = 0; i < program.nets.size(); ++i) {
    if (program.nets[i].name == name) root = i;
  }
  if (name.empty()) {
    root = program.mission;
    if (!root && program.nets.size() == 1) root = 0;
  }
  if (!root) {
    std::string names;
    for (const auto& n : program.nets) names += fmt::format("{}{}", names.empty() ? "" : ", ", n.name);
    return core::Error{core::ErrorCode::InvalidInput,
                       name.empty() ? fmt::format("no mission net: choose one of {} with --net", names)
                                    : fmt::format("no net '{}' (there are: {})", name, names)};
  }
  std::vector<PhaseExits> known;
  for (std::size_t i : detail::callees_first(program, *root)) {
    const CompiledNet& cn = program.nets[i];
    if (i == *root) return build_analysis_net(program, cn, known);
    AnalysisNet phase = build_analysis_net(program, cn, known);
    petri::QuestionOptions o = limits;
    o.terminal_places = phase.exits;
    PhaseExits exits{cn.name, std::vector<bool>(phase.exits.size(), false)};
    bool decided = true;
    for (std::size_t e = 0; e < phase.exits.size() && decided; ++e) {
      petri::Question q;
      q.kind = petri::QuestionKind::Reachable;
      q.predicate = petri::Predicate::compare({true, phase.exits[e], 0}, petri::CompareOp::Ge, {false, 0, 1});
      q.target = q.predicate;
      const petri::QuestionResult r = petri::answer_question(phase.net, q, o);
      decided = r.answer != petri::Answer::NotDecided;
      exits.reachable[e] = r.answer == petri::Answer::Yes;
    }
    if (decided) known.push_back(std::move(exits));
  }
  return core::Error{core::ErrorCode::Internal, "the net asked about was not visited"};
}

}  // namespace strata::coral
