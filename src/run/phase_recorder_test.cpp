// The summary's phases (session_run.h's PhaseRecorder): each depth-1 phase
// as it ends, bounded however many end (issue 39: a phase restarted in a
// loop made a 9.2 MB summary line).
#include <gtest/gtest.h>

#include "run/session_run.h"

namespace strata::run::detail {
namespace {

void start_and_end(PhaseRecorder& r, strategic::InstanceId id, std::string_view name, std::size_t exit_index) {
  r.phase_started({id, 0, name, "", 1, nullptr, 0.0});
  r.phase_ended({id, name, exit_index == 0 ? "complete" : "failed", exit_index, false, 0.0});
}

TEST(PhaseRecorder, TheSameEndingAgainIsOneEntryWithItsCount) {
  std::vector<std::string> phases;
  PhaseRecorder r(phases);
  start_and_end(r, 1, "1", 0);
  for (strategic::InstanceId i = 2; i < 1002; ++i) start_and_end(r, i, "2", 1);
  start_and_end(r, 2000, "3", 0);
  EXPECT_EQ((std::vector<std::string>{"1 completed", "2 aborted (x1000)", "3 completed"}), phases);
}

TEST(PhaseRecorder, PastItsBoundTheRestAreCounted) {
  std::vector<std::string> phases;
  PhaseRecorder r(phases);
  for (strategic::InstanceId i = 1; i <= 250; ++i) start_and_end(r, i, i % 2 ? "leg" : "turn", 0);
  ASSERT_EQ(kMaxPhaseEntries, phases.size());
  EXPECT_EQ("leg completed", phases.front());
  EXPECT_EQ("leg completed", phases[kMaxPhaseEntries - 2]);  // the 99th
  EXPECT_EQ("... and 151 more", phases.back());              // 99 kept, 151 counted
}

}  // namespace
}  // namespace strata::run::detail
