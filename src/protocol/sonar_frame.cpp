#include "protocol/sonar_frame.h"

#include <array>
#include <bit>
#include <cstring>

namespace strata::protocol {
namespace {

constexpr char kSync[4] = {'\xA5', 'S', 'N', 'R'};
constexpr std::uint8_t kVersion = 1;
constexpr std::size_t kHeader = 8;
constexpr std::size_t kTrailer = 4;
enum : std::uint8_t { kPing = 1, kStatus = 2, kEnd = 3 };

static_assert(std::endian::native == std::endian::little, "the sonar codec writes host order as little-endian");

const std::array<std::uint32_t, 256>& crc_table() {
  static const auto table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  return table;
}

template <typename T>
void put(std::string& out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  out.append(b, sizeof(T));
}

// Reads fixed-size fields from a payload; ok() false once one is missing.
class Reader {
 public:
  explicit Reader(std::string_view p) : p_(p) {}
  template <typename T>
  T get() {
    T v{};
    if (p_.size() - pos_ < sizeof(T)) {
      ok_ = false;
      return v;
    }
    std::memcpy(&v, p_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::string_view rest() {
    auto r = p_.substr(pos_);
    pos_ = p_.size();
    return r;
  }
  bool ok() const { return ok_; }
  bool done() const { return pos_ == p_.size(); }

 private:
  std::string_view p_;
  std::size_t pos_ = 0;
  bool ok_ = true;
};

std::optional<SonarFrame> decode_payload(std::uint8_t type, std::string_view payload) {
  Reader r(payload);
  if (type == kPing) {
    SonarPing p;
    p.time_s = r.get<double>();
    p.seq = r.get<std::uint32_t>();
    p.bearing_deg = r.get<float>();
    p.heading_deg = r.get<float>();
    p.x_m = r.get<float>();
    p.y_m = r.get<float>();
    p.range_m = r.get<float>();
    const auto n = r.get<std::uint16_t>();
    std::string_view bins = r.rest();
    if (!r.ok() || bins.size() != n) return std::nullopt;
    p.bins.assign(bins.begin(), bins.end());
    return p;
  }
  if (type == kStatus) {
    SonarStatus s;
    s.time_s = r.get<double>();
    const auto on = r.get<std::uint8_t>();
    s.pings_sent = r.get<std::uint32_t>();
    s.pings_dropped = r.get<std::uint32_t>();
    if (!r.ok() || !r.done() || on > 1) return std::nullopt;
    s.on = on == 1;
    return s;
  }
  if (type == kEnd) {
    SonarEnd e;
    e.time_s = r.get<double>();
    e.pings_sent = r.get<std::uint32_t>();
    e.pings_dropped = r.get<std::uint32_t>();
    if (!r.ok()) return std::nullopt;
    e.reason = std::string(r.rest());
    return e;
  }
  return std::nullopt;
}

}  // namespace

std::uint32_t crc32(std::string_view bytes, std::uint32_t crc) {
  const auto& t = crc_table();
  crc = ~crc;
  for (unsigned char c : bytes) crc = t[(crc ^ c) & 0xFFu] ^ (crc >> 8);
  return ~crc;
}

std::string encode_sonar(const SonarFrame& frame) {
  std::string payload;
  std::uint8_t type = 0;
  if (const auto* p = std::get_if<SonarPing>(&frame)) {
    type = kPing;
    const std::size_t n = std::min(p->bins.size(), kMaxSonarBins);
    payload.reserve(34 + n);
    put(payload, p->time_s);
    put(payload, p->seq);
    put(payload, p->bearing_deg);
    put(payload, p->heading_deg);
    put(payload, p->x_m);
    put(payload, p->y_m);
    put(payload, p->range_m);
    put(payload, static_cast<std::uint16_t>(n));
    payload.append(reinterpret_cast<const char*>(p->bins.data()), n);
  } else if (const auto* s = std::get_if<SonarStatus>(&frame)) {
    type = kStatus;
    put(payload, s->time_s);
    put(payload, static_cast<std::uint8_t>(s->on ? 1 : 0));
    put(payload, s->pings_sent);
    put(payload, s->pings_dropped);
  } else {
    const auto& e = std::get<SonarEnd>(frame);
    type = kEnd;
    put(payload, e.time_s);
    put(payload, e.pings_sent);
    put(payload, e.pings_dropped);
    payload += e.reason.substr(0, kMaxSonarPayload - payload.size());
  }
  std::string out(kSync, 4);
  out.reserve(kHeader + payload.size() + kTrailer);
  put(out, kVersion);
  put(out, type);
  put(out, static_cast<std::uint16_t>(payload.size()));
  out += payload;
  put(out, crc32(std::string_view(out).substr(4)));
  return out;
}

void SonarDecoder::feed(std::string_view bytes) {
  if (pos_ > 0 && pos_ >= buffer_.size() / 2) {
    buffer_.erase(0, pos_);
    pos_ = 0;
  }
  buffer_.append(bytes);
}

void SonarDecoder::skip(std::size_t n) {
  pos_ += n;
  skipped_bytes_ += n;
}

std::optional<SonarFrame> SonarDecoder::next() {
  for (;;) {
    std::string_view rest = std::string_view(buffer_).substr(pos_);
    // Look for the sync; keep a partial one at the end.
    const auto at = rest.find(std::string_view(kSync, 4));
    if (at == std::string_view::npos) {
      std::size_t keep = 0;
      for (std::size_t k = std::min<std::size_t>(3, rest.size()); k > 0; --k) {
        if (rest.substr(rest.size() - k) == std::string_view(kSync, k)) {
          keep = k;
          break;
        }
      }
      skip(rest.size() - keep);
      return std::nullopt;
    }
    if (at > 0) {
      skip(at);
      continue;
    }
    if (rest.size() < kHeader) return std::nullopt;
    const auto version = static_cast<std::uint8_t>(rest[4]);
    const auto type = static_cast<std::uint8_t>(rest[5]);
    std::uint16_t length = 0;
    std::memcpy(&length, rest.data() + 6, 2);
    if (version != kVersion || type < kPing || type > kEnd || length > kMaxSonarPayload) {
      ++bad_frames_;
      skip(1);
      continue;
    }
    if (rest.size() < kHeader + length + kTrailer) return std::nullopt;
    std::uint32_t crc = 0;
    std::memcpy(&crc, rest.data() + kHeader + length, 4);
    auto frame = crc == crc32(rest.substr(4, kHeader - 4 + length)) ? decode_payload(type, rest.substr(kHeader, length))
                                                                    : std::nullopt;
    if (!frame) {
      ++bad_frames_;
      skip(1);
      continue;
    }
    pos_ += kHeader + length + kTrailer;
    ++frames_;
    return frame;
  }
}

}  // namespace strata::protocol
