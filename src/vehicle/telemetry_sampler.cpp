#include "vehicle/telemetry_sampler.h"

#include <cmath>
#include <string>

#include <fmt/format.h>

#include "vehicle/wire_time.h"

namespace strata::vehicle {

protocol::Telemetry telemetry_message(const Telemetry& t) {
  protocol::Telemetry m;
  m.sim_time_s = wire_time(t.time_s);
  // Rounded to what the instruments resolve: 0.1 mm, 0.1 mm/s, 0.01 N.
  auto round_to = [](std::optional<double> v, double step) -> std::optional<double> {
    if (!v) return v;
    return std::round(*v / step) * step;
  };
  m.depth_m = round_to(t.measured_depth_m, 1e-4);
  m.filtered_depth_m = round_to(t.filtered_depth_m, 1e-4);
  m.rate_mps = round_to(t.rate_mps, 1e-4);
  m.thrust_n = round_to(t.thrust_n, 1e-2);
  m.setpoint_m = t.setpoint_m;
  m.heading_deg = std::fmod(*round_to(t.heading_deg, 1e-2), 360.0);  // 359.996 -> 0, not 360
  m.extras["true_depth"] = fmt::format("{:.4f}", t.depth_m);
  m.extras["mode"] = std::string(to_string(t.mode));
  // The horizontal plane, to the centimetre (mm/s for speed): the estimate
  // the vehicle steers by, the truth for plots and tests, and how sure the
  // estimate is. Open water only, so the tank's lines stay as they were.
  if (t.open_water) {
    m.extras["x"] = fmt::format("{:.2f}", t.x_m);
    m.extras["y"] = fmt::format("{:.2f}", t.y_m);
    m.extras["true_x"] = fmt::format("{:.2f}", t.true_x_m);
    m.extras["true_y"] = fmt::format("{:.2f}", t.true_y_m);
    m.extras["pos_sd"] = fmt::format("{:.2f}", t.position_sd_m);
    m.extras["speed"] = fmt::format("{:.3f}", t.speed_mps);
    if (t.altitude_m) m.extras["alt"] = fmt::format("{:.2f}", *t.altitude_m);
  }
  return m;
}

void TelemetrySampler::set_rate(double rate_hz, double now_s) {
  rate_hz_ = rate_hz;
  next_s_ = rate_hz > 0 ? now_s + 1.0 / rate_hz : 0.0;
}

std::optional<protocol::Telemetry> TelemetrySampler::sample(const Simulation& sim) {
  if (rate_hz_ <= 0 || sim.time_s() + 1e-9 < next_s_) return std::nullopt;
  protocol::Telemetry m = telemetry_message(sim.telemetry());
  next_s_ += 1.0 / rate_hz_;
  if (next_s_ < sim.time_s()) next_s_ = sim.time_s() + 1.0 / rate_hz_;
  return m;
}

}  // namespace strata::vehicle
