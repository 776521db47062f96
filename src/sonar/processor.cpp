#include "sonar/processor.h"

#include <algorithm>
#include <cmath>

namespace strata::sonar {
namespace {

bool usable(const protocol::SonarPing& p) {
  return !p.bins.empty() && p.range_m > 0.0f && std::isfinite(p.range_m) && std::isfinite(p.x_m) &&
         std::isfinite(p.y_m) && std::isfinite(p.heading_deg) && std::isfinite(p.bearing_deg);
}

}  // namespace

Processor::Processor(const ProcessorOptions& options)
    : options_(options), scan_(options.image), step_deg_(options.default_step_deg) {
  sweeps_.emplace_back();
}

std::optional<FrameReport> Processor::add_ping(const protocol::SonarPing& ping) {
  if (!usable(ping)) {
    ++unusable_;
    return std::nullopt;
  }
  std::optional<FrameReport> done;
  if (last_) {
    const double delta = normalise_deg(static_cast<double>(ping.bearing_deg) - last_->bearing_deg);
    if (std::abs(delta) > 1e-3) {
      const int direction = delta > 0 ? 1 : -1;
      const bool turned = direction_ != 0 && direction != direction_;
      if (frame_pings_ > 0 && (turned || swept_deg_ + std::abs(delta) > 360.0 + 1e-6)) done = complete_frame();
      direction_ = direction;
      swept_deg_ += std::abs(delta);
      // The step between successive pings (lost ones aside) is the width
      // each ping paints, so that a sweep leaves no gap between beams.
      const std::uint32_t apart = ping.seq > last_->seq ? ping.seq - last_->seq : 1;
      const double step = std::abs(delta) / apart;
      if (step <= 10.0) step_deg_ = step;
    }
  }
  scan_.paint(ping, std::clamp(step_deg_, 0.2, 10.0));
  if (auto echo = find_echo(ping, options_.echo)) sweeps_.back().push_back(*echo);
  if (!last_) last_.emplace();
  last_->time_s = ping.time_s;
  last_->seq = ping.seq;
  last_->bearing_deg = ping.bearing_deg;
  last_->heading_deg = ping.heading_deg;
  last_->x_m = ping.x_m;
  last_->y_m = ping.y_m;
  last_->range_m = ping.range_m;
  ++pings_;
  ++frame_pings_;
  return done;
}

std::optional<FrameReport> Processor::flush() {
  if (frame_pings_ == 0) return std::nullopt;
  FrameReport report = complete_frame();
  direction_ = 0;
  last_.reset();
  return report;
}

FrameReport Processor::complete_frame() {
  FrameReport r;
  r.frame = ++frames_;
  r.time_s = last_->time_s;
  r.frame_pings = frame_pings_;
  r.pings = pings_;
  r.vehicle = {last_->x_m, last_->y_m, last_->heading_deg};
  std::vector<EchoPoint> window;
  for (const auto& sweep : sweeps_) window.insert(window.end(), sweep.begin(), sweep.end());
  r.detection = detect(window, r.vehicle, options_.detect);
  scan_.centre_on(r.vehicle.x_m, r.vehicle.y_m);
  r.image = scan_.image();
  scan_.end_sweep();
  sweeps_.emplace_back();
  while (sweeps_.size() > static_cast<std::size_t>(std::max(options_.window_sweeps, 1))) sweeps_.pop_front();
  frame_pings_ = 0;
  swept_deg_ = 0.0;
  return r;
}

}  // namespace strata::sonar
