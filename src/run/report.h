#pragma once
// What a run did, for the summary, the studio and tests.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "protocol/message.h"
#include "run/error.h"
#include "strategic/executor.h"
#include "tactical/tactical_level.h"

namespace strata::run {

struct RunReport {
  // core/exit_codes.h: 0 only for a completed mission. For a run that never
  // started the run library leaves it 0 and says why in `error`; its caller
  // picks the code (cli::exit_code).
  int exit_code = 0;
  std::string mission_name;
  std::optional<strategic::MissionResult> result;  // unset if the mission never started
  std::optional<Error> error;                      // why it never started
  // The mission log could not be written to its end (the run itself went on).
  std::optional<Error> log_error;
  // What ended the run when it was not the mission itself: "SIGINT",
  // "SIGTERM", "SIGHUP", "studio", "limit"; "" otherwise.
  std::string stopped_by;
  // With stopped_by: how (run::StopMode): "interrupt", "abort", "hard".
  std::string stop_mode;
  bool link_lost = false;
  std::string link_lost_why;
  // "phoenix" (the line protocol) or "imc" (an IMC vehicle).
  std::string execution_level = "phoenix";
  // The vehicle stopped taking this run's commands (an IMC plan replaced by
  // another controller, or timed out): why; "" never.
  std::string vehicle_fault;
  // How the safe end surfaced an IMC vehicle: "reference" (z = 0), "abort"
  // (it took no Reference); "" not by the safe end, or not IMC.
  std::string surface_method;
  // IMC: what the link did not use, in a few words; "" not IMC.
  std::string imc_dropped;
  // The vehicle's own words for an exec or ood it answered 0 ("exec submerge
  // failed: ..."): the last such call's CallRecord::vehicle_said; "" none.
  std::string vehicle_reason;
  std::vector<std::string> phases;  // "initialize completed", depth-1 phases in the order they ended
  std::uint64_t primitive_calls = 0;
  double sim_time_s = 0.0;
  double wall_time_s = 0.0;
  bool lockstep = true;
  // The safe end (safe_end.h): what the run did itself after the mission.
  bool emergency_shutdown = false;  // it sent Figure 10's `done` (ood shutdown_network)
  std::string shutdown_error;       // ... unanswered: why ("" answered)
  bool emergency_surface = false;   // ... and before it commanded the surface (the link still worked)
  bool emergency_surfaced = false;  // ... and the vehicle answered surface_reached 1 (then or before)
  bool hurried = false;             // a second stop request cut the safe end short
  // Embedded vehicle only: its state when the run was over.
  std::optional<double> final_depth_m;
  std::optional<double> final_time_s;
  bool vehicle_watchdog_tripped = false;
  // The last telemetry heard (every vehicle: with --vehicle the only word on
  // its final state).
  std::optional<protocol::Telemetry> last_telemetry;
  // With a sonar folder: the Sonar Manager's exit status (nullopt if it was
  // not started or did not end), and one line on what it saw.
  std::optional<int> sonar_exit;
  std::string sonar_summary;
  std::string log_path;    // "" none
  bool log_dated = false;  // the log was (to be) a dated one in RunOptions::log_dir
  std::uint64_t log_lines = 0;
  std::uint64_t log_dropped = 0;  // lines past RunOptions::max_log_bytes, not written
  // With RunOptions::answers: how many of the script's answers the run used,
  // of how many, and why it left the script ("" it did not).
  std::size_t answers_used = 0;
  std::size_t answers_total = 0;
  std::string answers_diverged;
  std::string answers_first_unused;  // the first entry not used; "" all were
  // With RunOptions::trace: every primitive call, in the order they completed.
  std::vector<tactical::CallRecord> trace;
};

// "completed", "aborted", "failed: interrupted by SIGINT", ...: how the run
// ended in a few words, for the summary's first line; its first word is the
// mission log's outcome.
std::string ending_text(const RunReport& report);

// The summary people read after a run (the CLI prints it): the ending, the
// reason, phases, times, the vehicle's final state, what the safe end did,
// the log.
std::string summary_text(const RunReport& report);

// The same as one JSON document (`strata run --format json`; its fields in
// docs/architecture.md, "The run's summary as JSON"). A mission that never
// started gives {"started": false, "exit_code": N}.
nlohmann::json summary_json(const RunReport& report);

}  // namespace strata::run
