#pragma once
// `strata run` as the CLI does it: a run::RunSession with the console as its
// observer (and any others), the operator's signals routed to its stop(),
// and the summary printed after it. Kept apart from the command line so
// tests run whole missions in-process.
#include <ostream>
#include <vector>

#include "run/observer.h"
#include "run/options.h"
#include "run/report.h"
#include "run/session.h"
#include "cli/verbosity.h"

namespace strata::cli {

using run::RunOptions;
using run::RunReport;

struct ConsoleOptions {
  bool tty = false;                          // a live status line instead of plain event lines
  bool handle_signals = false;               // SIGINT, SIGTERM, SIGHUP stop the run (the CLI's main thread only)
  std::vector<run::RunObserver*> observers;  // told after the console
  // Quiet: the summary alone (no event lines, no status line); verbose: a
  // line for every primitive call and its answer too.
  Verbosity verbosity = Verbosity::Normal;
  // The summary as one JSON document (run::summary_json) and no event lines.
  bool json = false;
};

// Runs the mission; console lines and the summary go to out, problems to err.
RunReport run_mission(const RunOptions& options, std::ostream& out, std::ostream& err,
                      const ConsoleOptions& console = {});

// What a signal does to a run: the first ends it through the safe end (exit
// 128 + N), a second one cuts the safe end short.
void stop_on_signal(run::RunSession& session, int signal);

}  // namespace strata::cli
