#pragma once
// The sonar stream (docs/protocol.md, "Sonar stream"): the vehicle's second
// TCP socket, on which it sends the scanning sonar's pings as soon as they
// are acquired, to the Sonar Manager.
//
// Binary frames, little-endian, so a reader can find its place again after
// garbage or a cut:
//
//   offset size
//   0      4    sync: A5 53 4E 52 ("\xA5SNR")
//   4      1    version: 1
//   5      1    type: 1 ping, 2 status, 3 end
//   6      2    payload length N (at most kMaxSonarPayload)
//   8      N    payload
//   8+N    4    CRC-32 (IEEE 802.3, as zlib's crc32) of bytes 4 .. 8+N-1
//
// A reader that meets anything else (no sync, an unknown version or type, a
// length over the limit, a CRC that does not match) drops one byte and looks
// for the next sync. Payloads (f64/f32/u32/u16 little-endian):
//   ping:   time_s f64, seq u32, bearing_deg f32, heading_deg f32,
//           x_m f32, y_m f32, range_m f32, bin count u16, bins u8[count]
//   status: time_s f64, on u8, pings_sent u32, pings_dropped u32
//   end:    time_s f64, pings_sent u32, pings_dropped u32, reason (rest, UTF-8)
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace strata::protocol {

inline constexpr std::size_t kMaxSonarPayload = 8192;
inline constexpr std::size_t kMaxSonarBins = 4096;

// One ping of the mechanically scanned beam: echo intensity in range bins
// along one bearing. Angles in degrees: heading is the compass heading of the
// bow (0 = tank +y, 90 = tank +x, clockwise); bearing is the beam's angle
// from the bow, positive to starboard. Bin i covers ranges
// [i, i+1) * range_m / bins.size(). x_m, y_m: the vehicle's position in the
// tank (its navigation estimate) when the ping was sent.
struct SonarPing {
  double time_s = 0.0;
  std::uint32_t seq = 0;  // 0, 1, 2, ... per vehicle run: a gap is a lost ping
  float bearing_deg = 0.0f;
  float heading_deg = 0.0f;
  float x_m = 0.0f;
  float y_m = 0.0f;
  float range_m = 0.0f;
  std::vector<std::uint8_t> bins;
  friend bool operator==(const SonarPing&, const SonarPing&) = default;
};

// Sent when a reader connects and whenever the sonar starts or stops.
struct SonarStatus {
  double time_s = 0.0;
  bool on = false;
  std::uint32_t pings_sent = 0;
  std::uint32_t pings_dropped = 0;  // not sent: this reader was too slow
  friend bool operator==(const SonarStatus&, const SonarStatus&) = default;
};

// The last frame of a stream: the vehicle is stopping (the run is over).
struct SonarEnd {
  double time_s = 0.0;
  std::uint32_t pings_sent = 0;
  std::uint32_t pings_dropped = 0;
  std::string reason;
  friend bool operator==(const SonarEnd&, const SonarEnd&) = default;
};

using SonarFrame = std::variant<SonarPing, SonarStatus, SonarEnd>;

std::uint32_t crc32(std::string_view bytes, std::uint32_t crc = 0);

// The frame's bytes. A ping with more than kMaxSonarBins bins, or an end
// reason that does not fit, is cut to fit.
std::string encode_sonar(const SonarFrame& frame);

// Finds frames in a byte stream that arrives in chunks of any size. It holds
// the bytes fed and not yet taken by next(): a reader that calls next() until
// nullopt after each feed() keeps at most one frame's bytes. Not thread-safe.
class SonarDecoder {
 public:
  void feed(std::string_view bytes);
  // The next whole frame, or nullopt until more bytes come.
  std::optional<SonarFrame> next();

  std::uint64_t frames() const { return frames_; }
  // Bytes dropped while looking for a sync, and frames whose header or CRC
  // was wrong (each counted once).
  std::uint64_t skipped_bytes() const { return skipped_bytes_; }
  std::uint64_t bad_frames() const { return bad_frames_; }
  std::size_t buffered() const { return buffer_.size() - pos_; }

 private:
  void skip(std::size_t n);
  std::string buffer_;
  std::size_t pos_ = 0;
  std::uint64_t frames_ = 0;
  std::uint64_t skipped_bytes_ = 0;
  std::uint64_t bad_frames_ = 0;
};

}  // namespace strata::protocol
