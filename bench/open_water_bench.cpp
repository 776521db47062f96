// Issue 20's cross-track targets: the RMS cross-track error of the true
// position along a straight 200 m leg after the turn settles
// (src/vehicle/leg_trial.h), with no current (target <= 2 m) and with a
// 0.2 m/s cross current (target <= 5 m), at the surface and at 5 m depth,
// averaged over five noise seeds. Counters are metres; the wall time is the
// cost of simulating one leg.
#include <benchmark/benchmark.h>

#include "vehicle/leg_trial.h"

namespace {

using strata::vehicle::trial::LegTrial;
using strata::vehicle::trial::run_leg;

void leg(benchmark::State& state, double current, bool submerged, double calibration_s) {
  double rms = 0.0, worst = 0.0, max = 0.0, seconds = 0.0;
  for (auto _ : state) {
    rms = worst = max = seconds = 0.0;
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
      const auto r = run_leg(LegTrial{current, submerged, calibration_s, seed});
      rms += r.rms_m / 5.0;
      worst = std::max(worst, r.rms_m);
      max = std::max(max, r.max_m);
      seconds += r.time_s / 5.0;
    }
  }
  state.counters["xte_rms_m"] = rms;
  state.counters["xte_rms_worst_m"] = worst;
  state.counters["xte_max_m"] = max;
  state.counters["leg_s"] = seconds;
}

BENCHMARK_CAPTURE(leg, surface_no_current, 0.0, false, 0.0)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(leg, surface_cross_0_2, 0.2, false, 0.0)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(leg, submerged_no_current_calibrated_120s, 0.0, true, 120.0)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(leg, submerged_cross_0_2_calibrated_120s, 0.2, true, 120.0)->Unit(benchmark::kMillisecond);
// Diving at once: the current is known only from the few fixes taken while
// the vehicle leaves the surface, and dead reckoning carries that error.
BENCHMARK_CAPTURE(leg, submerged_no_current_uncalibrated, 0.0, true, 0.0)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(leg, submerged_cross_0_2_uncalibrated, 0.2, true, 0.0)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
