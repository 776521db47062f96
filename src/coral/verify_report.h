#pragma once
// The two forms of a VerifyReport: text for people (`strata verify`, and
// `strata run` when it refuses a mission) and JSON for tools and the studio
// (`strata verify --format json`; docs/verification.md has the schema).
#include <string>

#include <nlohmann/json.hpp>

#include "coral/verifier.h"

namespace strata::coral {

std::string_view status_name(Property::Status status);  // "holds", "fails", "undecided"

// How much of a report `verify_text` shows.
enum class VerifyDetail {
  Problems,  // the nets with a property that fails or is not decided, and the summary (`-q`)
  Nets,      // one line per net that is fine, those nets in full, the summary (the default)
  Full,      // every net, its properties, bounds and P-invariants (`-v`)
};

// The report for people; counterexamples under the properties that fail.
// A net shown in full at Problems or Nets leaves out the properties that
// hold.
std::string verify_text(const VerifyReport& report, VerifyDetail detail = VerifyDetail::Full);
// Only what fails, with counterexamples, and one line per net that is
// fine; for `strata run`.
std::string verify_failures_text(const VerifyReport& report);
// One step of a counterexample: "fire check_depth: ASK depth_reached".
std::string step_text(const TraceStep& step);

nlohmann::ordered_json verify_json(const VerifyReport& report);

}  // namespace strata::coral
