#pragma once
// A verifier witness as a script of vehicle answers (docs/verification.md,
// "Witnesses as runs"): the answers a path of an analysis net needs from
// the vehicle, in the order the engine issues the calls, so that `strata run
// --answers FILE` (run/answers.h reads the file) can drive a real run down
// the same path. The format, version 1:
//
//   { "strata_answers": 1,
//     "mission": "missions/tank/tank.coral",     // as verify was given it
//     "net": "dive_from_surface",                // the net the path is in
//     "from": "question 'EF abort >= 1'",        // or "no_deadlock counterexample"
//     "answers": [ { "step": 2, "net": "dive_from_surface", "transition": "read_setpoint",
//                    "action": "exec", "primitive": "next_setpt_data", "answer": 1 },
//                  { "step": 4, ..., "action": "ask", "primitive": "depth_filter_off", "answer": 0 },
//                  { "step": 9, ..., "action": "phase", "primitive": "initialize", "answer": "done" } ],
//     "path": [ "1. fire read_setpoint: EXEC next_setpt_data", ... ] }   // for people only
//
// `step` is the answer's step in the path (from 1); `answer` is 1 or 0 for
// exec, ask and ood, and the exit name for a phase.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "coral/analysis.h"
#include "coral/program.h"
#include "coral/verifier.h"
#include "petri/net.h"

namespace strata::coral {

inline constexpr int kAnswersFormatVersion = 1;

// The steps of `path` (transitions of `an`, built for a net of `program`).
std::vector<TraceStep> trace_of(const Program& program, const AnalysisNet& an,
                                const std::vector<petri::TransitionId>& path);

// The answers file of a path in net `net`. Answers are ordered by the step
// that issued their action (each answer taken by the earliest firing of its
// transition still waiting for it), then by the action's place in the
// transition: the order of the calls, which is the order a run meets them
// in, whatever order the path answered calls in flight together.
nlohmann::ordered_json witness_answers_json(const std::string& mission, const std::string& net, const std::string& from,
                                            const std::vector<TraceStep>& steps);

// How many answers the file of these steps holds.
std::size_t answer_count(const std::vector<TraceStep>& steps);

}  // namespace strata::coral
