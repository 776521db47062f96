#pragma once
// Processing: pings in, frames out (docs/sonar.md). Each ping is painted
// into the scan image and gives at most one echo point; a frame is complete
// at each end of a sweep, when the bearing turns back (or, for a sonar that
// turns all the way round, after 360 degrees): the image, and the walls and
// target detected in the echo points of the last `window_sweeps` sweeps.
// Not thread-safe: the processing thread owns it.
#include <cstdint>
#include <deque>
#include <optional>
#include <vector>

#include "protocol/sonar_frame.h"
#include "sonar/detect.h"
#include "sonar/scan_image.h"

namespace strata::sonar {

struct ProcessorOptions {
  ImageOptions image;
  EchoOptions echo;
  DetectOptions detect;
  int window_sweeps = 2;          // sweeps of echo points detection looks at
  double default_step_deg = 1.8;  // the beam width until two pings show the step
};

struct FrameReport {
  std::uint64_t frame = 0;        // 1, 2, ... per Processor
  double time_s = 0.0;            // the vehicle's time at the frame's last ping
  std::uint64_t frame_pings = 0;  // pings painted in this frame's sweep
  std::uint64_t pings = 0;        // pings processed so far
  Pose vehicle;                   // at the frame's last ping
  Detection detection;
  GreyImage image;  // centred on `vehicle` (to half a pixel)
};

class Processor {
 public:
  explicit Processor(const ProcessorOptions& options = {});

  // Processes one ping. When it starts a new sweep, returns the frame of
  // the sweep before it (this ping is then the new sweep's first).
  std::optional<FrameReport> add_ping(const protocol::SonarPing& ping);
  // The frame of the sweep under way, if it has any ping; the next ping
  // starts a new sweep (call when the sonar stops or the stream ends).
  std::optional<FrameReport> flush();

  std::uint64_t pings() const { return pings_; }
  std::uint64_t frames() const { return frames_; }
  // Pings with no bins, no range, or a position or angle that is not a number.
  std::uint64_t unusable() const { return unusable_; }
  const ScanImage& scan() const { return scan_; }

 private:
  FrameReport complete_frame();

  ProcessorOptions options_;
  ScanImage scan_;
  std::deque<std::vector<EchoPoint>> sweeps_;  // the newest (under way) last
  std::uint64_t pings_ = 0, frames_ = 0, unusable_ = 0, frame_pings_ = 0;
  std::optional<protocol::SonarPing> last_;  // without its bins
  int direction_ = 0;                        // of the bearing in this sweep: +1, -1, 0 not yet known
  double swept_deg_ = 0.0;
  double step_deg_;
};

}  // namespace strata::sonar
