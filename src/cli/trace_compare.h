#pragma once
// Primitive-call traces of two runs, side by side (`strata compare`): the
// paper's claim that the Strategic level can be swapped with no change
// below it, checked call by call.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "tactical/tactical_level.h"

namespace strata::cli {

// One call as compared: what was sent, what came back, and when.
struct TraceRow {
  std::string call;    // "exec sleep 1", "report \"text\""
  std::string answer;  // "1", "0", or "error: ..."
  double sim_time_s = 0.0;
  std::optional<core::CallVerb> verb;      // the call's verb; nullopt for an unknown primitive (not compared)
  bool failed = false;                     // the call failed: answer is "error: ..." (not compared)
  std::size_t repeats = 1;                 // command_rows(): how many calls in a row this one stands for (not compared)
  bool guard = false;                      // a guard's own poll (dropped by command_rows; not compared)
  bool operator==(const TraceRow&) const;  // sim time to the millisecond
};

TraceRow trace_row(const tactical::CallRecord& record);
std::vector<TraceRow> trace_rows(const std::vector<tactical::CallRecord>& records);

// The commands of a trace, for two runs on different execution levels
// (`strata compare --vehicle-b imc://...`): exec, ood and report rows only,
// without their times, and a run of identical rows (a poll loop's `exec
// sleep 1` between its asks) as one row with its count in `repeats`, no
// guard's polls (when a guard polls depends on the vehicle's timing), and a
// failed call's answer as "error". Asks, times and the words of an error
// depend on the vehicle; the commands and their order do not.
std::vector<TraceRow> command_rows(const std::vector<TraceRow>& rows);

// The index of the first row that differs (a missing row differs), or
// nullopt when the traces are the same.
std::optional<std::size_t> first_difference(const std::vector<TraceRow>& a, const std::vector<TraceRow>& b);

struct SideBySideOptions {
  std::string title_a, title_b;
  // Rows shown around the first difference (or at the end when the traces
  // are the same); nullopt: every row.
  std::optional<std::size_t> context;
};

// The two traces as a table, the first difference marked with "<<<".
std::string side_by_side(const std::vector<TraceRow>& a, const std::vector<TraceRow>& b,
                         const SideBySideOptions& options);

}  // namespace strata::cli
