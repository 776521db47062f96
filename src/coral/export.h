#pragma once
// A mission's nets for other tools (`strata export`, docs/verification.md):
// the analysis net of each (analysis.h) as PNML, so a model checker sees the
// vehicle's answers as Strata's verifier does, and as Graphviz DOT for
// people, with the TACTIC and PHASE actions on their transitions.
#include <string>

#include "coral/analysis.h"
#include "coral/program.h"

namespace strata::coral {

// PNML 2009 P/T text of the net's analysis net (petri::write_pnml): ids are
// the analysis net's names ("check_depth.depth_reached.yes"). `phase_exits`
// as for build_analysis_net: pass reachable_phase_exits of a verification
// to write the nets it explored.
std::string export_pnml(const Program& program, const CompiledNet& net,
                        const std::vector<PhaseExits>& phase_exits = {});

// Graphviz DOT of the analysis net: places as circles with their initial
// tokens (exits doubled), mission transitions as boxes labelled with their
// actions, in-flight places dashed, outcome transitions small and labelled
// with the answer, arc weights other than 1 on the arcs.
std::string export_dot(const Program& program, const CompiledNet& net, const std::vector<PhaseExits>& phase_exits = {});

}  // namespace strata::coral
