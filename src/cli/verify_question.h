#pragma once
// `strata verify MISSION --question Q` and `--replay SEQ`: the questions of
// cli/net_question.h asked of the analysis net of one net of a CORAL
// mission (coral/verify_question.h). The options are registered on the
// verify command; cmd_verify.cpp dispatches here when one of them is given.
#include <string>

#include "cli/net_question.h"

namespace strata::cli {

// Names as the mission writes them. Exit as run_pnml_question; 65 for a
// mission that does not compile; 64 for an unknown --net.
int run_mission_question(const std::string& mission, const std::string& catalogue, const QuestionFlags& flags,
                         const std::string& format, const QuestionLimits& limits);

}  // namespace strata::cli
