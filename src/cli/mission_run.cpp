#include "cli/mission_run.h"

#include <optional>

#include <fmt/format.h>

#include "cli/console.h"
#include "cli/run_problems.h"
#include "cli/signal_watcher.h"
#include "core/exit_codes.h"

namespace strata::cli {

void stop_on_signal(run::RunSession& session, int signal) {
  const std::string name = signal_name(signal);
  session.stop(name, fmt::format("interrupted by {}", name), kExitSignalBase + signal);
}

RunReport run_mission(const RunOptions& options, std::ostream& out, std::ostream& err,
                      const ConsoleOptions& console_options) {
  run::RunSession session(options);
  const Verbosity verbosity = console_options.verbosity;
  Console console(out, console_options.tty, verbosity == Verbosity::Verbose);
  if (verbosity != Verbosity::Quiet && !console_options.json) session.add_observer(console);
  for (run::RunObserver* o : console_options.observers) session.add_observer(*o);
  std::optional<SignalWatcher> signals;
  if (console_options.handle_signals) signals.emplace([&session](int signal) { stop_on_signal(session, signal); });
  // What the mission text holds (warnings too) is printed before anything
  // moves; why the run cannot start, after run() says so.
  (void)session.load();
  print_load_findings(err, session.loaded(), options);
  RunReport report = session.run();
  signals.reset();
  print_run_errors(err, report);
  if (console_options.json) {
    out << run::summary_json(report).dump(2) << "\n";
  } else {
    out << run::summary_text(report);
  }
  out.flush();
  if (report.exit_code == kExitInternal && !report.result) err << "strata run: the mission did not start\n";
  return report;
}

}  // namespace strata::cli
