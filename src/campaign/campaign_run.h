#pragma once
// A campaign run end to end: the folder prepared, the cases run by the pool
// (or in this process), every result written to results.jsonl as it comes,
// a progress line, and report.json and report.html written at the end —
// also when a stop request ended it early (they then say so).
#include <csignal>
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "campaign/case_run.h"
#include "campaign/spec.h"
#include "core/result.h"

namespace strata::campaign {

struct CampaignOptions {
  std::string out_dir;  // required
  int jobs = 1;         // worker processes; 0: run in this process, no fork
  KeepLogs keep_logs = KeepLogs::Failed;
  double case_wall_limit_s = 120.0;
  std::string command;  // the command line, for the report
  // Progress on this stream: a line redrawn in place on a terminal, plain
  // lines (every tenth of the cases, or every 5 s) otherwise; null: none.
  std::ostream* progress = nullptr;
  bool progress_tty = false;
  const volatile std::sig_atomic_t* stop_requests = nullptr;
};

struct CampaignOutcome {
  std::uint64_t planned = 0, done = 0, failed = 0;
  bool interrupted = false;
  double wall_s = 0.0;
  // Cases whose time from the fault to a bound's end was past the proven
  // worst case: failures of the timing analysis (report.json, "bounds").
  std::uint64_t past_proven_bound = 0;
};

// Errors: Io when the folder or a file in it cannot be written.
core::Result<CampaignOutcome> run_campaign(const Spec& spec, const std::vector<std::uint64_t>& indices,
                                           const CampaignOptions& options);

}  // namespace strata::campaign
