#include "cli/run_problems.h"

#include <fmt/format.h>

#include "coral/verify_report.h"
#include "core/diagnostic_printer.h"
#include "core/exit_codes.h"

namespace strata::cli {

int exit_code(const run::Error& error) {
  switch (error.kind) {
    case run::ErrorKind::Usage: return kExitUsage;
    case run::ErrorKind::Invalid:
    case run::ErrorKind::FailsVerification: return kExitInvalid;
    case run::ErrorKind::Unreadable:
    case run::ErrorKind::LogUnwritable:
    case run::ErrorKind::VehicleUnavailable: return kExitIo;
  }
  return kExitInternal;
}

std::string error_line(std::string_view command, const run::Error& error) {
  if (error.input.empty()) return fmt::format("{}: {}", command, error.message);
  return fmt::format("{}: {}: {}", command, error.input, error.message);
}

void print_load_findings(std::ostream& err, const run::LoadedMission& loaded, const run::RunOptions& options) {
  core::print_diagnostics(err, loaded.sources, loaded.diagnostics, "strata run");
  if (!loaded.verification) return;
  const coral::VerifyReport& v = *loaded.verification;
  if (v.ok()) {
    // one_safe, no_dead: information, not a veto.
    if (!v.all_hold()) err << "strata run: warning:\n" << coral::verify_failures_text(v);
    return;
  }
  err << "strata run: " << options.mission << " fails verification:\n" << coral::verify_failures_text(v);
  if (options.unverified) {
    err << "strata run: warning: running a mission that fails verification (--unverified)\n";
  } else if (!options.answers.empty()) {
    err << "strata run: warning: running a mission that fails verification, to follow the answers of --answers\n";
  }
}

void print_run_errors(std::ostream& err, run::RunReport& report) {
  if (report.error) {
    err << error_line("strata run", *report.error) << "\n";
    if (report.error->kind == run::ErrorKind::LogUnwritable && report.log_dated) {
      err << "(the default log: --log FILE puts it elsewhere, --no-log runs without one)\n";
    }
    report.exit_code = exit_code(*report.error);
  }
  if (report.log_error) {
    err << error_line("strata run", *report.log_error) << "\n";
    report.exit_code = exit_code(*report.log_error);
  }
}

int print_coral_load(std::ostream& err, const run::CoralLoad& load, std::string_view command, std::string_view suffix) {
  core::print_diagnostics(err, load.sources, load.diagnostics, command);
  const auto failed = load.error();
  if (!failed) return kExitOk;
  err << error_line(command, *failed) << suffix << "\n";
  return exit_code(*failed);
}

}  // namespace strata::cli
