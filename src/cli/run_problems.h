#pragma once
// The CLI's words for what the run library returns as values: the exit code
// and the `strata COMMAND: ...` line of a run::Error, and the diagnostics a
// load found, printed for people before a run starts.
#include <ostream>
#include <string>
#include <string_view>

#include "run/coral_load.h"
#include "run/error.h"
#include "run/loaded_mission.h"
#include "run/options.h"
#include "run/report.h"

namespace strata::cli {

// 64 usage; 65 an invalid input or a mission that fails verification; 74
// an input that cannot be read, a log that cannot be written, a vehicle
// that cannot be reached (core/exit_codes.h).
int exit_code(const run::Error& error);

// "strata run: --answers: MESSAGE": the command, the input when named, the
// message.
std::string error_line(std::string_view command, const run::Error& error);

// Every diagnostic and rule message of the load (warnings too), then what
// verification found: the properties that do not hold and, when the run goes
// on regardless, a warning that says why.
void print_load_findings(std::ostream& err, const run::LoadedMission& loaded, const run::RunOptions& options);

// After a run: why it never started, or that its log is incomplete, as a
// `strata run: ...` line, and report.exit_code set to match.
void print_run_errors(std::ostream& err, run::RunReport& report);

// A CORAL load for a command that is not `run`: its diagnostics and, when it
// did not compile, "COMMAND: PATH: 2 errorsSUFFIX". Returns 0, or the exit
// code for the failure.
int print_coral_load(std::ostream& err, const run::CoralLoad& load, std::string_view command,
                     std::string_view suffix = "");

}  // namespace strata::cli
