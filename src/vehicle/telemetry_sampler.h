#pragma once
// The vehicle's telemetry as the protocol sends it: sampled at the rate the
// controller asked for (`telemetry ID RATE`), in simulated time, and rounded
// to what the instruments resolve. Pure; the server sends what it returns.
#include <optional>

#include "protocol/message.h"
#include "vehicle/simulation.h"

namespace strata::vehicle {

// One telemetry line from the simulation's state now: times on the wire's
// microsecond, depths and rate to 0.1 mm (mm/s), thrust to 0.01 N, heading to
// 0.01 degree in [0, 360); true_depth and mode as extras.
protocol::Telemetry telemetry_message(const Telemetry& t);

class TelemetrySampler {
 public:
  // From now_s on, one sample every 1 / rate_hz simulated seconds, the first
  // one period from now; rate_hz <= 0 stops sampling.
  void set_rate(double rate_hz, double now_s);
  void stop() { rate_hz_ = 0.0; }
  double rate_hz() const { return rate_hz_; }
  // After a step: the sample due by now, if one is. A sampler that fell
  // behind (a rate faster than the cycle) skips to one period from now.
  std::optional<protocol::Telemetry> sample(const Simulation& sim);

 private:
  double rate_hz_ = 0.0;
  double next_s_ = 0.0;
};

}  // namespace strata::vehicle
