#include "vehicle/telemetry_sampler.h"

#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace strata::vehicle {
namespace {

// The times of the samples taken over `seconds` of simulated time.
std::vector<double> sample_times(TelemetrySampler& sampler, Simulation& sim, double seconds) {
  std::vector<double> times;
  const double end_s = sim.time_s() + seconds;
  while (sim.time_s() + 1e-9 < end_s) {
    sim.step();
    if (auto m = sampler.sample(sim)) times.push_back(m->sim_time_s);
  }
  return times;
}

TEST(TelemetrySampler, SamplesAtTheRateAskedTheFirstOnePeriodLater) {
  Simulation sim(default_params(), Scenario::nominal());
  TelemetrySampler sampler;
  EXPECT_EQ(std::vector<double>{}, sample_times(sampler, sim, 1.0)) << "no rate, no samples";
  sampler.set_rate(2.0, sim.time_s());
  EXPECT_EQ((std::vector<double>{1.5, 2.0, 2.5, 3.0}), sample_times(sampler, sim, 2.0));
  sampler.stop();
  EXPECT_EQ(std::vector<double>{}, sample_times(sampler, sim, 1.0));
}

TEST(TelemetrySampler, ARateFasterThanTheCycleGivesOneSamplePerCycle) {
  Simulation sim(default_params(), Scenario::nominal());
  TelemetrySampler sampler;
  sampler.set_rate(100.0, sim.time_s());
  EXPECT_EQ(10u, sample_times(sampler, sim, 1.0).size());
}

TEST(TelemetrySampler, TheMessageIsRoundedToWhatTheInstrumentsResolve) {
  Telemetry t;
  t.time_s = 5.6000000000000005;
  t.depth_m = 1.234567;
  t.measured_depth_m = 1.23456789;
  t.heading_deg = 359.996;
  const protocol::Telemetry m = telemetry_message(t);
  EXPECT_EQ(5.6, m.sim_time_s);
  ASSERT_TRUE(m.depth_m);
  EXPECT_NEAR(1.2346, *m.depth_m, 1e-12);
  EXPECT_EQ(0.0, *m.heading_deg) << "359.996 is 0, not 360";
  EXPECT_EQ("1.2346", m.extras.at("true_depth"));
}

}  // namespace
}  // namespace strata::vehicle
