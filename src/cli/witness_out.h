#pragma once
// `strata verify MISSION --witness-out FILE`: a counterexample or a
// question's witness written as a script of vehicle answers
// (coral/witness.h) that `strata run --answers FILE` follows.
#include <string>
#include <vector>

#include "coral/analysis.h"
#include "coral/program.h"
#include "coral/verifier.h"
#include "petri/net.h"

namespace strata::cli {

// The counterexample of the first property of the report that fails with
// one (blocking properties first; in net `net` only when it is not empty),
// written to file. Returns 0 when written; 1 when there is none (said on
// stderr, nothing written); 64 for a --net the report does not have; 74
// when the file cannot be written.
int write_report_witness(const coral::VerifyReport& report, const std::string& mission, const std::string& net,
                         const std::string& file);

// The path (transitions of `an`, a net of `program`) written to file as
// the witness of `question`. Returns 0, or 74 when the file cannot be written.
int write_path_witness(const coral::Program& program, const coral::AnalysisNet& an,
                       const std::vector<petri::TransitionId>& path, const std::string& mission,
                       const std::string& question, const std::string& file);

}  // namespace strata::cli
