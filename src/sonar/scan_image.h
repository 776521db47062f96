#pragma once
// The scan image: the sonar's pings painted from polar (bearing, range) into
// a square, north-up grey picture of the tank around the vehicle
// (docs/sonar.md, "The image").
//
// Geometry: tank +y is up, +x right; a pixel is `metres_per_px()` wide, the
// half width is the sonar's range. The image is anchored in the tank: a ping
// is painted from the vehicle's position when it was sent, so the picture
// stays true while the vehicle moves; centre_on() re-anchors it on whole
// pixels (content moves with the tank, not with the vehicle).
//
// Intensity to grey (the display curve), for a bin value v in 0..255:
//   grey = 255 * ln(1 + k * max(0, v - floor)) / ln(1 + k * (255 - floor))
// with floor = ImageOptions::floor_intensity and k = ImageOptions::log_gain:
// the noise floor is black, weak echoes are lifted, strong ones compressed.
//
// Not thread-safe: one processing thread owns it.
#include <cstdint>
#include <vector>

#include "protocol/sonar_frame.h"

namespace strata::sonar {

// 8-bit grey, row-major, the top row (largest tank y) first.
struct GreyImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;
  std::uint8_t at(int col, int row) const {
    return pixels[static_cast<std::size_t>(row) * static_cast<std::size_t>(width) + static_cast<std::size_t>(col)];
  }
};

struct ImageOptions {
  int size_px = 400;            // width and height
  double floor_intensity = 24;  // bin values at or below are black
  double log_gain = 0.05;       // k of the display curve (larger: more lift for weak echoes)
  double fade = 0.5;            // per sweep, for pixels no ping of the sweep repainted
};

class ScanImage {
 public:
  explicit ScanImage(const ImageOptions& options = {});

  // Paints the ping's beam, `beam_width_deg` wide about heading + bearing,
  // along its bins. Within one sweep a pixel keeps the brightest value
  // painted on it; the first paint of a new sweep replaces the old value.
  // The first ping, or one with another range_m, clears the image, sets the
  // scale and centres it on the ping's position.
  void paint(const protocol::SonarPing& ping, double beam_width_deg);
  // The sweep is over: every pixel fades (those the next sweep repaints are
  // replaced anyway, the rest dim sweep after sweep).
  void end_sweep();
  // Moves the image's centre by whole pixels to within half a pixel of
  // (x_m, y_m); what was painted stays where it is in the tank.
  void centre_on(double x_m, double y_m);

  const GreyImage& image() const { return image_; }
  bool empty() const { return range_m_ <= 0.0; }
  double metres_per_px() const { return metres_per_px_; }
  double centre_x_m() const { return centre_x_m_; }
  double centre_y_m() const { return centre_y_m_; }
  // Where a tank point falls, in pixels (column, row; fractional, the pixel
  // (c, r) covers [c, c+1) x [r, r+1)).
  double col_of(double x_m) const;
  double row_of(double y_m) const;
  std::uint8_t grey(std::uint8_t intensity) const { return grey_[intensity]; }

 private:
  void reset(const protocol::SonarPing& ping);
  ImageOptions options_;
  GreyImage image_;
  std::vector<std::uint32_t> sweep_of_;  // per pixel: the sweep that last painted it
  std::uint32_t sweep_ = 1;
  double range_m_ = 0.0;
  double metres_per_px_ = 0.0;
  double centre_x_m_ = 0.0;
  double centre_y_m_ = 0.0;
  std::uint8_t grey_[256];
};

}  // namespace strata::sonar
