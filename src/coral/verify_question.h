#pragma once
// Questions (petri/question.h: deadlock, EF φ, AG φ) on the analysis net of
// one net of a mission (analysis.h, docs/verification.md "The analysis
// net"): the net each mission net is verified on, with its place names
// (the mission's, plus "TRANSITION.PRIMITIVE" in-flight places). A PHASE
// action's outcomes are narrowed to the exits its phase can reach, each
// decided by the same search (EF exit >= 1 on the phase's own analysis
// net); a phase whose exits a limit left undecided may end at any of them,
// as in verify_program. Markings with an exit marked have no successors,
// so the search uses no stubborn sets on nets with exits.
#include <cstdint>
#include <string_view>

#include "core/result.h"
#include "coral/analysis.h"
#include "coral/program.h"
#include "petri/question.h"

namespace strata::coral {

// The analysis net of net `name` of the program (empty: the mission net;
// or the only net when there is no mission net). `limits` bounds each
// phase's exit searches (max_states, max_memory_bytes, progress).
// Errors: InvalidInput naming the nets there are.
core::Result<AnalysisNet> question_analysis_net(const Program& program, std::string_view name,
                                                const petri::QuestionOptions& limits);

}  // namespace strata::coral
