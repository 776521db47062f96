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

TEST(TelemetryMessage, OpenWaterAddsThePlaneAndTheTankLineIsUnchanged) {
  Telemetry t;
  t.x_m = 12.345;
  t.y_m = -3.0;
  t.true_x_m = 13.0;
  t.true_y_m = -2.5;
  t.position_sd_m = 4.25;
  t.speed_mps = 0.8004;
  t.altitude_m = 7.5;
  EXPECT_EQ(0u, telemetry_message(t).extras.count("x"));  // the tank: as before
  t.open_water = true;
  const auto m = telemetry_message(t);
  EXPECT_EQ("12.35", m.extras.at("x"));
  EXPECT_EQ("-3.00", m.extras.at("y"));
  EXPECT_EQ("13.00", m.extras.at("true_x"));
  EXPECT_EQ("-2.50", m.extras.at("true_y"));
  EXPECT_EQ("4.25", m.extras.at("pos_sd"));
  EXPECT_EQ("0.800", m.extras.at("speed"));
  EXPECT_EQ("7.50", m.extras.at("alt"));
  t.altitude_m.reset();
  EXPECT_EQ(0u, telemetry_message(t).extras.count("alt"));
}

}  // namespace
}  // namespace strata::vehicle
