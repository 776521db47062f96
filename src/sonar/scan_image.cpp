#include "sonar/scan_image.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>

#include "core/units.h"

namespace strata::sonar {

using core::kRadPerDeg;

ScanImage::ScanImage(const ImageOptions& options) : options_(options) {
  assert(options_.size_px >= 8);
  image_.width = image_.height = options_.size_px;
  image_.pixels.assign(static_cast<std::size_t>(options_.size_px) * static_cast<std::size_t>(options_.size_px), 0);
  sweep_of_.assign(image_.pixels.size(), 0);
  const double floor = std::clamp(options_.floor_intensity, 0.0, 254.0);
  const double k = std::max(options_.log_gain, 1e-6);
  const double top = std::log1p(k * (255.0 - floor));
  for (int v = 0; v < 256; ++v) {
    const double x = std::max(0.0, v - floor);
    grey_[v] = static_cast<std::uint8_t>(std::lround(255.0 * std::log1p(k * x) / top));
  }
}

double ScanImage::col_of(double x_m) const { return options_.size_px / 2.0 + (x_m - centre_x_m_) / metres_per_px_; }

double ScanImage::row_of(double y_m) const { return options_.size_px / 2.0 - (y_m - centre_y_m_) / metres_per_px_; }

void ScanImage::reset(const protocol::SonarPing& ping) {
  range_m_ = ping.range_m;
  metres_per_px_ = range_m_ / (options_.size_px / 2.0);
  centre_x_m_ = ping.x_m;
  centre_y_m_ = ping.y_m;
  std::fill(image_.pixels.begin(), image_.pixels.end(), 0);
  std::fill(sweep_of_.begin(), sweep_of_.end(), 0);
}

void ScanImage::paint(const protocol::SonarPing& ping, double beam_width_deg) {
  const std::size_t bins = ping.bins.size();
  if (bins == 0 || !(ping.range_m > 0.0f)) return;
  if (empty() || std::abs(ping.range_m - range_m_) > 1e-6 * range_m_) reset(ping);

  // Forward mapping with oversampling: K rays across the beam, one sample
  // every half pixel along each, enough that the beam's far end (its widest)
  // leaves no unpainted pixel between rays.
  const int size = options_.size_px;
  const double radius_px = size / 2.0;
  const double half_rad = std::max(beam_width_deg, 0.0) * kRadPerDeg / 2.0;
  const int rays = std::max(1, static_cast<int>(std::ceil(radius_px * 2.0 * half_rad * 1.5)));
  const double theta = (static_cast<double>(ping.heading_deg) + ping.bearing_deg) * kRadPerDeg;
  const double c0 = col_of(ping.x_m);
  const double r0 = row_of(ping.y_m);
  const double bins_per_px = static_cast<double>(bins) / radius_px;
  const int steps = static_cast<int>(2.0 * radius_px);
  for (int k = 0; k < rays; ++k) {
    const double a = theta - half_rad + (k + 0.5) * (2.0 * half_rad / rays);
    const double dc = std::sin(a);
    const double dr = -std::cos(a);  // rows grow southwards
    for (int s = 0; s < steps; ++s) {
      const double t = (s + 0.5) * 0.5;
      const auto bin = static_cast<std::size_t>(t * bins_per_px);
      if (bin >= bins) break;
      const auto col = static_cast<int>(std::floor(c0 + t * dc));
      const auto row = static_cast<int>(std::floor(r0 + t * dr));
      if (col < 0 || row < 0 || col >= size || row >= size) continue;
      const auto p = static_cast<std::size_t>(row) * static_cast<std::size_t>(size) + static_cast<std::size_t>(col);
      const std::uint8_t v = grey_[ping.bins[bin]];
      if (sweep_of_[p] != sweep_) {
        image_.pixels[p] = v;
        sweep_of_[p] = sweep_;
      } else if (v > image_.pixels[p]) {
        image_.pixels[p] = v;
      }
    }
  }
}

void ScanImage::end_sweep() {
  const double fade = std::clamp(options_.fade, 0.0, 1.0);
  for (auto& px : image_.pixels) px = static_cast<std::uint8_t>(px * fade);
  ++sweep_;
}

void ScanImage::centre_on(double x_m, double y_m) {
  if (empty()) return;
  const auto dc = static_cast<int>(std::lround((x_m - centre_x_m_) / metres_per_px_));
  const auto dr = static_cast<int>(std::lround(-(y_m - centre_y_m_) / metres_per_px_));
  if (dc == 0 && dr == 0) return;
  const int size = options_.size_px;
  std::vector<std::uint8_t> pixels(image_.pixels.size(), 0);
  std::vector<std::uint32_t> sweeps(sweep_of_.size(), 0);
  for (int row = 0; row < size; ++row) {
    const int from_row = row + dr;
    if (from_row < 0 || from_row >= size) continue;
    for (int col = 0; col < size; ++col) {
      const int from_col = col + dc;
      if (from_col < 0 || from_col >= size) continue;
      const auto to = static_cast<std::size_t>(row) * static_cast<std::size_t>(size) + static_cast<std::size_t>(col);
      const auto from =
          static_cast<std::size_t>(from_row) * static_cast<std::size_t>(size) + static_cast<std::size_t>(from_col);
      pixels[to] = image_.pixels[from];
      sweeps[to] = sweep_of_[from];
    }
  }
  image_.pixels = std::move(pixels);
  sweep_of_ = std::move(sweeps);
  centre_x_m_ += dc * metres_per_px_;
  centre_y_m_ -= dr * metres_per_px_;
}

}  // namespace strata::sonar
