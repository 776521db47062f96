#pragma once
// One case, run in this process: a run::RunSession in lockstep against the
// embedded vehicle, its scenario handed over in memory, watched by an
// observer that gathers the expectations' figures and the coverage. Nothing
// is started per case but the run itself (no process, no file read but the
// mission's own).
#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "campaign/cases.h"
#include "campaign/expectations.h"
#include "campaign/spec.h"
#include "tactical/tactical_level.h"

namespace strata::campaign {

enum class KeepLogs { All, Failed, None };

struct CaseRunConfig {
  // The campaign's folder ("" none): mission logs go to DIR/logs/case-I.jsonl
  // and a failing case's scenario to DIR/scenarios/case-I.toml.
  std::string out_dir;
  KeepLogs keep_logs = KeepLogs::Failed;
  // Called when a failing case starts again to write its log (run_case):
  // a worker says so to the pool, whose wall-clock limit a case has then
  // counts again from there.
  std::function<void()> on_run_again;
};

// The case's line of results.jsonl: index, inputs, outcome, reason, phases,
// pass, each check with its figure, figures, coverage, timings, and the
// files kept. Never throws for a mission that goes wrong: that is a result.
nlohmann::ordered_json run_case(const Spec& spec, const Case& c, const CaseRunConfig& config);

// The line for a case that never gave its own (its worker died): outcome
// "crashed" with why, every expectation failed through "ran".
nlohmann::ordered_json crashed_case(const Spec& spec, const Case& c, const std::string& why);

// Whether a call counts among the EXECs the vehicle refused (refused_execs,
// no_refused_exec): an exec answered 0, or one the Execution level refused
// (CallError::Kind::Refused). Decided by the call's verb and error kind, never
// by its words: a timeout or a lost link is not a refusal.
bool refused_exec(const tactical::CallRecord& call);

// The command that runs the case alone again.
std::string repro_command(const Spec& spec, const Case& c);

// The `strata run` arguments (after `strata`) that run case c as a plain
// run: its mission, scenario_file (the case's scenario, written out), the
// vehicle (case_params_file, the case's whole parameter file, when not
// empty; else the spec's --params), the spec's limits and the family's
// answers. A failing case's repro_run line is these, quoted.
std::vector<std::string> repro_run_args(const Spec& spec, const Case& c, const std::string& scenario_file,
                                        const std::string& case_params_file);

}  // namespace strata::campaign
