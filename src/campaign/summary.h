#pragma once
// What a campaign found, gathered case by case as results arrive (memory
// grows with the failures kept and a few numbers per case, not with the
// cases' lines): the counts, the outcome matrix of family x injection time,
// time-to-surface after a fault, proven bounds against the measured times, the failing cases with their repro
// commands, and coverage. report.json is to_json(); report.html is drawn
// from that same JSON.
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "campaign/spec.h"
#include "core/result.h"

namespace strata::campaign {

// The failing cases listed one by one in the report; the rest are counted.
inline constexpr std::size_t kMaxListedFailures = 500;
// Columns of the outcome matrix: injection times beyond this many distinct
// values are binned.
inline constexpr std::size_t kMaxMatrixColumns = 40;

struct CampaignRun {
  std::uint64_t planned = 0;  // cases the campaign meant to run
  int workers = 1;
  double wall_s = 0.0;
  bool interrupted = false;
  std::string command;  // how it was started, for the report
};

class Summary {
 public:
  explicit Summary(const Spec& spec);

  void add(const nlohmann::ordered_json& line);
  // Every transition of a CORAL mission's nets ("net.transition"), so that
  // coverage can name those no case fired.
  void set_transitions(const std::string& mission, std::vector<std::string> transitions);

  std::uint64_t done() const { return done_; }
  std::uint64_t failed() const { return failed_; }
  // Cases past a proven bound (the timing analysis unsound for them).
  std::uint64_t past_proven_bound() const;

  // report.json.
  nlohmann::ordered_json to_json(const CampaignRun& run) const;

 private:
  struct Cell {
    std::uint64_t done = 0, failed = 0;
    std::map<std::string, std::uint64_t> outcomes;
  };
  struct Row {
    std::string mission, family;
    std::vector<double> edges;  // column c holds at_s in [edges[c], edges[c+1]); one column without a fault
    std::vector<std::string> labels;
    std::vector<Cell> cells;
  };
  struct Surfacing {
    std::optional<double> limit_s;
    std::vector<double> times_s;
    std::uint64_t never = 0;  // the fault happened; the vehicle was not seen at the surface
  };

  // A proven bound (an expectation set's `bound`) against one mission's cases.
  struct BoundSeen {
    std::optional<double> proven_s;  // the analysis's worst case (the checks' limit)
    std::uint64_t measured = 0, exceeded = 0, unproven = 0;
    double max_s = 0.0;
    std::string note;  // the first case's note without a proven bound (PROLOG rules, an unbounded answer)
  };

  std::size_t column(const Row& row, double at_s) const;

  const Spec& spec_;
  std::uint64_t done_ = 0, passed_ = 0, failed_ = 0;
  std::map<std::string, std::uint64_t> outcomes_;
  std::map<std::string, std::pair<std::uint64_t, std::uint64_t>> families_;  // done, failed
  std::vector<Row> rows_;                                                    // mission-major, family-minor
  std::map<std::string, Surfacing> surfacing_;                               // by family
  std::map<std::pair<std::string, std::string>, BoundSeen> bounds_;          // by mission, family
  std::vector<nlohmann::ordered_json> failures_;
  std::map<std::string, std::map<std::string, std::uint64_t>> coverage_;  // mission -> item -> cases
  std::vector<double> case_wall_s_;
  std::map<std::string, std::vector<std::string>> transitions_;  // mission -> every transition
};

// The p-th percentile (0..100) of values by nearest rank; values unsorted.
double percentile(std::vector<double> values, double p);

}  // namespace strata::campaign

namespace strata::campaign {

// Every transition of a CORAL mission and its imports, "net.transition", in
// load order; compiled here without running anything (no threads: safe in
// the parent before the workers fork). An error when it does not compile.
core::Result<std::vector<std::string>> mission_transitions(const std::string& coral_path);

}  // namespace strata::campaign
