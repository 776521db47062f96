#pragma once
// `strata campaign --compare A.jsonl B.jsonl`: what changed between two
// campaigns' results (two versions of a mission, of the vehicle, of the
// spec's limits). Cases are matched by their inputs (mission, family, fault,
// seed), not by index, so a spec that gained a family still lines up.
#include <string>
#include <vector>

#include "core/result.h"

namespace strata::campaign {

struct CompareReport {
  std::size_t matched = 0;
  std::vector<std::string> only_a, only_b;  // "index: inputs"
  std::vector<std::string> newly_failing, newly_passing, outcome_changed;
  std::vector<std::string> figure_changed;  // a check's figure moved (same pass/fail)
  bool differs() const {
    return !only_a.empty() || !only_b.empty() || !newly_failing.empty() || !newly_passing.empty() ||
           !outcome_changed.empty();
  }
};

// Errors: Io (a file cannot be read), InvalidInput (a line is not a result,
// "path:line: ...").
core::Result<CompareReport> compare_results(const std::string& a_path, const std::string& b_path);

// The report for people, a section per kind of change.
std::string compare_text(const CompareReport& report, const std::string& a_path, const std::string& b_path);

}  // namespace strata::campaign
