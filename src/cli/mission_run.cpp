#include "cli/mission_run.h"

#include <optional>

#include <fmt/format.h>

#include "cli/console.h"
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
  Console console(out, console_options.tty);
  session.add_observer(console);
  for (run::RunObserver* o : console_options.observers) session.add_observer(*o);
  std::optional<SignalWatcher> signals;
  if (console_options.handle_signals) signals.emplace([&session](int signal) { stop_on_signal(session, signal); });
  RunReport report = session.run(err);
  signals.reset();
  out << run::summary_text(report);
  out.flush();
  if (report.exit_code == kExitInternal && !report.result) err << "strata run: the mission did not start\n";
  return report;
}

}  // namespace strata::cli
