// The scan image: a known tank drawn where it is (checked on the PNG the
// manager writes, decoded again), the display curve, fading.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/units.h"
#include "sonar/output.h"
#include "core/file.h"
#include "sonar/png_io.h"
#include "sonar/processor.h"
#include "sonar/scan_image.h"
#include "sonar/test_support.h"

namespace strata::sonar {
namespace {

using core::kRadPerDeg;
using testing::PingSynth;
using testing::SynthConfig;

// The brightest pixel within `r` pixels of (col, row).
int brightest_near(const GreyImage& image, double col, double row, int r) {
  int best = -1;
  for (int dr = -r; dr <= r; ++dr) {
    for (int dc = -r; dc <= r; ++dc) {
      const int c = static_cast<int>(std::floor(col)) + dc, w = static_cast<int>(std::floor(row)) + dr;
      if (c >= 0 && w >= 0 && c < image.width && w < image.height) best = std::max<int>(best, image.at(c, w));
    }
  }
  return best;
}

// Feeds whole sweeps and returns the frame of the last one.
FrameReport last_frame(PingSynth& synth, int sweeps, const ProcessorOptions& options = {}) {
  Processor processor(options);
  std::optional<FrameReport> last;
  for (const auto& ping : synth.sweeps(sweeps)) {
    if (auto f = processor.add_ping(ping)) last = std::move(f);
  }
  if (auto f = processor.flush()) last = std::move(f);
  EXPECT_TRUE(last.has_value());
  return last ? std::move(*last) : FrameReport{};
}

// For each beam direction in the sweep that meets a wall squarely enough
// for a strong echo (incidence under 60 degrees): bright within 2 px of
// where the wall is; dark along the open water between the vehicle and the
// wall (speckle aside: the median black, 1 sample in 20 at most not dark).
void expect_walls_drawn(const GreyImage& image, const PingSynth& synth, double centre_x, double centre_y) {
  const auto& c = synth.config();
  const double px_per_m = image.width / 2.0 / c.range_m;
  int checked = 0;
  for (double bearing = -55.0; bearing <= 55.0; bearing += 5.0) {
    const double compass = c.heading_deg + bearing;
    const double wall = synth.wall_range(compass);
    if (wall > c.range_m - 0.3) continue;
    const double dx = std::sin(compass * kRadPerDeg), dy = std::cos(compass * kRadPerDeg);
    const double hit_x = synth.x_m() + wall * dx;
    const bool on_x_wall = std::abs(hit_x) < 1e-6 || std::abs(hit_x - c.tank_x_m) < 1e-6;
    if (std::abs(on_x_wall ? dx : dy) < 0.5) continue;
    auto col = [&](double r) { return image.width / 2.0 + (synth.x_m() + r * dx - centre_x) * px_per_m; };
    auto row = [&](double r) { return image.height / 2.0 - (synth.y_m() + r * dy - centre_y) * px_per_m; };
    EXPECT_GE(brightest_near(image, col(wall), row(wall), 2), 128)
        << "no wall at bearing " << bearing << ", " << wall << " m";
    std::vector<int> water;
    for (double r = 1.0; r < wall - 0.5; r += 0.05) {
      water.push_back(image.at(static_cast<int>(col(r)), static_cast<int>(row(r))));
    }
    ASSERT_FALSE(water.empty());
    const auto not_dark = std::count_if(water.begin(), water.end(), [](int v) { return v >= 64; });
    EXPECT_LE(not_dark, static_cast<long>(water.size() / 20 + 1)) << "open water not dark at bearing " << bearing;
    std::nth_element(water.begin(), water.begin() + static_cast<long>(water.size() / 2), water.end());
    EXPECT_LT(water[water.size() / 2], 16) << "open water not dark at bearing " << bearing;
    ++checked;
  }
  EXPECT_GE(checked, 12);
}

TEST(ScanImage, WallsOfAKnownTankAreBrightWhereTheyAreInTheWrittenPng) {
  SynthConfig config;  // 12 x 8 m tank, vehicle at (7, 4.5) heading 45: north wall 3.5 m, east wall 5 m
  config.spike_rate = 0.0;
  PingSynth synth(config);
  FrameReport frame = last_frame(synth, 2);
  ASSERT_EQ(400, frame.image.width);

  const auto dir = testing::fresh_dir("walls_png");
  auto out = OutputDir::open(dir);
  ASSERT_TRUE(out) << out.error().message;
  auto name = out.value().write_frame(frame.frame, frame.image);
  ASSERT_TRUE(name) << name.error().message;
  EXPECT_EQ("scan_00002.png", name.value());
  auto png = read_png(dir / name.value());
  ASSERT_TRUE(png) << png.error().message;
  ASSERT_EQ(frame.image.pixels, png.value().pixels);
  auto latest = read_png(dir / "latest.png");
  ASSERT_TRUE(latest) << latest.error().message;
  EXPECT_EQ(frame.image.pixels, latest.value().pixels);

  expect_walls_drawn(png.value(), synth, config.x_m, config.y_m);
  // Behind the bow's walls, beyond the corner: nothing was painted.
  EXPECT_EQ(0, png.value().at(2, 2));
}

TEST(ScanImage, StaysTrueToTheTankWhileTheVehicleMoves) {
  SynthConfig config;
  config.x_m = 3.0;
  config.y_m = 4.0;
  config.heading_deg = 80.0;
  config.vx_mps = 0.4;  // 1.3 m a sweep: the image must not smear the walls
  config.spike_rate = 0.0;
  PingSynth synth(config);
  FrameReport frame = last_frame(synth, 3);
  // The frame is centred on the vehicle at its last ping (to half a pixel);
  // the wall check goes from where the vehicle is now.
  EXPECT_NEAR(synth.x_m() - config.vx_mps * config.ping_interval_s, frame.vehicle.x_m, 1e-4);
  expect_walls_drawn(frame.image, synth, frame.vehicle.x_m, frame.vehicle.y_m);
}

TEST(ScanImage, DisplayCurveIsBlackUpToTheFloorThenRisesToWhite) {
  ImageOptions options;
  ScanImage scan(options);
  EXPECT_EQ(0, scan.grey(0));
  EXPECT_EQ(0, scan.grey(static_cast<std::uint8_t>(options.floor_intensity)));
  EXPECT_EQ(255, scan.grey(255));
  for (int v = 1; v < 256; ++v)
    EXPECT_LE(scan.grey(static_cast<std::uint8_t>(v - 1)), scan.grey(static_cast<std::uint8_t>(v)));
  // The log curve lifts weak echoes: a quarter of the way up is well over a quarter bright.
  EXPECT_GT(scan.grey(static_cast<std::uint8_t>(options.floor_intensity + 58)), 128);
}

TEST(ScanImage, AnOldSweepFadesAndANewOneReplacesIt) {
  ScanImage scan;
  protocol::SonarPing ping;
  ping.range_m = 10.0f;
  ping.bins.assign(200, 255);
  scan.paint(ping, 2.0);
  const int col = 200, row = 200 - 50;  // 5 m ahead (north) of the vehicle
  ASSERT_EQ(255, scan.image().at(col, row));
  scan.end_sweep();
  EXPECT_EQ(127, scan.image().at(col, row));
  scan.end_sweep();
  EXPECT_EQ(63, scan.image().at(col, row));
  ping.bins.assign(200, 0);
  scan.paint(ping, 2.0);  // a weaker return in a new sweep replaces, it does not keep the max
  EXPECT_EQ(0, scan.image().at(col, row));
}

TEST(ScanImage, ReadPngSaysWhatIsWrong) {
  const auto dir = testing::fresh_dir("bad_png");
  auto missing = read_png(dir / "none.png");
  ASSERT_FALSE(missing);
  EXPECT_EQ(core::ErrorCode::Io, missing.error().code);
  ASSERT_TRUE(core::write_file_atomically(dir / "text.png", "not a png"));
  auto text = read_png(dir / "text.png");
  ASSERT_FALSE(text);
  EXPECT_EQ(core::ErrorCode::InvalidInput, text.error().code);
}

}  // namespace
}  // namespace strata::sonar
