#include "protocol/sonar_frame.h"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

namespace strata::protocol {
namespace {

SonarPing ping(std::uint32_t seq, std::size_t bins = 200) {
  SonarPing p;
  p.time_s = 12.5 + seq * 0.05;
  p.seq = seq;
  p.bearing_deg = -45.0f + static_cast<float>(seq);
  p.heading_deg = 90.0f;
  p.x_m = 2.5f;
  p.y_m = 4.0f;
  p.range_m = 10.0f;
  for (std::size_t i = 0; i < bins; ++i) p.bins.push_back(static_cast<std::uint8_t>((i * 7 + seq) & 0xFF));
  return p;
}

std::vector<SonarFrame> drain(SonarDecoder& d) {
  std::vector<SonarFrame> out;
  while (auto f = d.next()) out.push_back(std::move(*f));
  return out;
}

TEST(SonarFrame, CrcIsIeee) {
  // The check value of CRC-32/ISO-HDLC.
  EXPECT_EQ(0xCBF43926u, crc32("123456789"));
}

TEST(SonarFrame, EveryKindRoundTrips) {
  const std::vector<SonarFrame> frames = {ping(0), SonarStatus{1.5, true, 3, 1},
                                          SonarEnd{99.0, 1200, 4, "the run is over"}, ping(7, 0)};
  std::string bytes;
  for (const auto& f : frames) bytes += encode_sonar(f);
  SonarDecoder d;
  d.feed(bytes);
  EXPECT_EQ(frames, drain(d));
  EXPECT_EQ(0u, d.skipped_bytes());
  EXPECT_EQ(0u, d.bad_frames());
  EXPECT_EQ(0u, d.buffered());
}

TEST(SonarFrame, BytesMayComeOneAtATime) {
  const std::string bytes = encode_sonar(ping(1)) + encode_sonar(ping(2));
  SonarDecoder d;
  std::vector<SonarFrame> got;
  for (char c : bytes) {
    d.feed(std::string_view(&c, 1));
    for (auto& f : drain(d)) got.push_back(std::move(f));
  }
  ASSERT_EQ(2u, got.size());
  EXPECT_EQ(ping(2), std::get<SonarPing>(got[1]));
}

TEST(SonarFrame, AReaderResynchronisesAfterGarbageAndADamagedFrame) {
  std::string damaged = encode_sonar(ping(2));
  damaged[40] ^= 0x10;  // a bin flipped on the way: the CRC no longer matches
  const std::string bytes = "garbage\xA5SN\xA5SNR\x01\x01\xFF\xFF" + encode_sonar(ping(1)) + "\xA5" + damaged +
                            "more junk" + encode_sonar(ping(3));
  SonarDecoder d;
  d.feed(bytes);
  const auto got = drain(d);
  ASSERT_EQ(2u, got.size());
  EXPECT_EQ(1u, std::get<SonarPing>(got[0]).seq);
  EXPECT_EQ(3u, std::get<SonarPing>(got[1]).seq);
  EXPECT_GE(d.bad_frames(), 2u);  // the too-long header and the damaged ping
  EXPECT_GT(d.skipped_bytes(), 0u);
}

TEST(SonarFrame, AnOverlongPingIsCutToTheLimit) {
  SonarPing p = ping(0, kMaxSonarBins + 100);
  SonarDecoder d;
  d.feed(encode_sonar(p));
  auto f = d.next();
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(kMaxSonarBins, std::get<SonarPing>(*f).bins.size());
}

RC_GTEST_PROP(SonarFrame, FramesSurviveGarbageBetweenThemAndAnyChunking, ()) {
  const auto n = *rc::gen::inRange(1, 12);
  std::string bytes;
  std::vector<SonarFrame> sent;
  for (int i = 0; i < n; ++i) {
    bytes += *rc::gen::container<std::string>(*rc::gen::inRange(0, 40), rc::gen::arbitrary<char>());
    SonarPing p = ping(static_cast<std::uint32_t>(i), *rc::gen::inRange<std::size_t>(0, 300));
    sent.emplace_back(p);
    bytes += encode_sonar(p);
  }
  SonarDecoder d;
  std::vector<SonarFrame> got;
  std::size_t at = 0;
  while (at < bytes.size()) {
    const auto k = *rc::gen::inRange<std::size_t>(1, 64);
    d.feed(std::string_view(bytes).substr(at, k));
    at += k;
    for (auto& f : drain(d)) got.push_back(std::move(f));
  }
  RC_ASSERT(got == sent);
}

}  // namespace
}  // namespace strata::protocol
