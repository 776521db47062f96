#pragma once
// A measurement, shared by bench/open_water_bench.cpp (which prints it) and
// open_water_test.cpp (which holds it to issue 20's targets): how closely the
// simulated Phoenix follows a straight 200 m track line after its turn onto
// it, as the RMS of the TRUE position's cross-track error.
//
// The vehicle starts at the origin heading north, at the surface; the line
// runs east from (0, 0) to (250, 0), so it turns 90 degrees onto it. The
// error is sampled once a cycle while the true along-track position is in
// [50, 250] m: the turn has settled by 50 m. A cross current flows north.
// Depth: at the surface (GPS fixes once a second), or at 5 m, diving at once
// or after calibration_s adrift at the surface (the navigation learns the
// current from its fixes there, and dead reckoning then allows for it).
// Header-only: test and benchmark support, not part of the model.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "vehicle/simulation.h"

namespace strata::vehicle::trial {

struct LegTrial {
  double current_north_mps = 0.0;
  bool submerged = false;
  double calibration_s = 0.0;  // at the surface, before the leg
  std::uint64_t seed = 1;
};

struct LegResult {
  double rms_m = 0.0;
  double max_m = 0.0;
  int samples = 0;
  double time_s = 0.0;      // simulated, from the start of the leg to its end
  double final_sd_m = 0.0;  // the estimate's horizontal 1-sigma at the end
};

inline LegResult run_leg(const LegTrial& trial) {
  Scenario s = Scenario::nominal(trial.seed);
  s.world.open_water = true;
  s.world.current_y_mps = trial.current_north_mps;
  s.seabed.depth_m = 60.0;
  Simulation sim(default_params(), s);
  LegResult r;
  if (!sim.start_network().ok()) return r;
  sim.advance(trial.calibration_s);
  if (trial.submerged && !sim.goto_depth(5.0).ok()) return r;
  const Guidance line{GuidanceMode::Track, 0.0, 0.0, 250.0, 0.0};
  if (!sim.track(line.x0_m, line.y0_m, line.x1_m, line.y1_m).ok()) return r;
  const double t0 = sim.time_s();
  double sum = 0.0;
  while (sim.pose().x_m < 250.0 && sim.time_s() - t0 < 1200.0) {
    sim.step();
    if (sim.pose().x_m < 50.0) continue;
    const double e = cross_track_m(line, sim.pose().x_m, sim.pose().y_m);
    sum += e * e;
    r.max_m = std::max(r.max_m, std::abs(e));
    ++r.samples;
  }
  r.time_s = sim.time_s() - t0;
  r.final_sd_m = sim.navigator().position_sd_m();
  r.rms_m = r.samples > 0 ? std::sqrt(sum / r.samples) : INFINITY;
  return r;
}

}  // namespace strata::vehicle::trial
