// The IMC codec by example: packets written out byte by byte from the
// specification, a round trip of every message, and every way a datagram
// is dropped. The properties are codec_property_test.cpp.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <set>
#include <string>
#include <variant>
#include <vector>

#include <gtest/gtest.h>

#include "imc/codec.h"
#include "imc/codec_test_support.h"

namespace strata::imc {
namespace {

using testing::datagram;
using testing::test_header;
using Bytes = std::vector<std::uint8_t>;

Drop drop_of(const Bytes& bytes) {
  auto result = decode(bytes);
  EXPECT_TRUE(std::holds_alternative<Drop>(result)) << "decoded, expected a drop";
  return std::holds_alternative<Drop>(result) ? std::get<Drop>(result) : Drop::Filtered;
}

Bytes encoded(const Packet& p) {
  auto bytes = encode(p);
  EXPECT_TRUE(bytes.ok()) << (bytes.ok() ? "" : bytes.error().message);
  return bytes.ok() ? bytes.value() : Bytes{};
}

// ---- golden packets, written from the specification -----------------------------

TEST(ImcGolden, Heartbeat) {
  const Bytes expected = testing::with_crc({
      0x54, 0xFE,                                      // sync
      0x96, 0x00,                                      // mgid 150
      0x00, 0x00,                                      // size 0
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xF8, 0x3F,  // timestamp 1.5
      0x01, 0x40, 0x05,                                // src 0x4001, src_ent 5
      0xD1, 0x00, 0xFF,                                // dst 0x00D1, dst_ent 0xFF
  });
  EXPECT_EQ(expected, encoded(Packet{test_header(), Heartbeat{}}));
  auto back = decode(expected);
  ASSERT_TRUE(std::holds_alternative<Packet>(back));
  const Packet& p = std::get<Packet>(back);
  EXPECT_EQ(Heartbeat::kId, p.header.mgid);
  EXPECT_EQ(0, p.header.size);
  EXPECT_EQ(1.5, p.header.timestamp);
  EXPECT_EQ(0x4001, p.header.src);
  EXPECT_TRUE(std::holds_alternative<Heartbeat>(p.message));
}

TEST(ImcGolden, ReferenceWithInlineSpeedAndZ) {
  const Bytes payload = {
      0x07,                                            // flags LOCATION|SPEED|Z
      0x92, 0x01,                                      // speed: DesiredSpeed (402)
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xF8, 0x3F,  //   value 1.5
      0x00,                                            //   speed_units m/s
      0x91, 0x01,                                      // z: DesiredZ (401)
      0x00, 0x00, 0x00, 0x40,                          //   value 2.0f
      0x01,                                            //   z_units DEPTH
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xE0, 0x3F,  // lat 0.5
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xD0, 0xBF,  // lon -0.25
      0x00, 0x00, 0x00, 0x00,                          // radius 0
  };
  ASSERT_EQ(39u, payload.size());
  const Bytes expected = datagram(479, payload);
  const Packet packet{test_header(), testing::sample_reference()};
  EXPECT_EQ(expected, encoded(packet));
  auto back = decode(expected);
  ASSERT_TRUE(std::holds_alternative<Packet>(back));
  EXPECT_EQ(packet.message, std::get<Packet>(back).message);
  EXPECT_EQ(39, std::get<Packet>(back).header.size);
}

TEST(ImcGolden, PlanControlStartingOneFollowReference) {
  const Bytes payload = {
      0x00, 0x00,              // type REQUEST, op START
      0x07, 0x00,              // request_id 7
      0x01, 0x00, 'p',         // plan_id "p"
      0x00, 0x00,              // flags
      0x27, 0x02,              // arg: PlanSpecification (551)
      0x01, 0x00, 'p',         //   plan_id "p"
      0x00, 0x00,              //   description ""
      0x00, 0x00,              //   vnamespace ""
      0x00, 0x00,              //   variables: none
      0x01, 0x00, 'm',         //   start_man_id "m"
      0x01, 0x00,              //   maneuvers: 1
      0x28, 0x02,              //   PlanManeuver (552)
      0x01, 0x00, 'm',         //     maneuver_id "m"
      0xDE, 0x01,              //     data: FollowReference (478)
      0x01, 0x40,              //       control_src 0x4001
      0x05,                    //       control_ent 5
      0x00, 0x00, 0x20, 0x41,  //       timeout 10
      0x00, 0x00, 0xA0, 0x40,  //       loiter_radius 5
      0x00, 0x00, 0x80, 0x3F,  //       altitude_interval 1
      0x00, 0x00,              //     start_actions: none
      0x00, 0x00,              //     end_actions: none
      0x00, 0x00,              //   transitions: none
      0x00, 0x00,              //   start_actions: none
      0x00, 0x00,              //   end_actions: none
      0x00, 0x00,              // info ""
  };
  const Bytes expected = datagram(559, payload);
  const Packet packet{test_header(), testing::follow_reference_plan()};
  EXPECT_EQ(expected, encoded(packet));
  auto back = decode(expected);
  ASSERT_TRUE(std::holds_alternative<Packet>(back));
  const auto& pc = std::get<PlanControl>(std::get<Packet>(back).message);
  const auto* spec = pc.arg.get_if<PlanSpecification>();
  ASSERT_NE(nullptr, spec);
  ASSERT_EQ(1u, spec->maneuvers.size());
  const auto* fr = spec->maneuvers[0].data.get_if<FollowReference>();
  ASSERT_NE(nullptr, fr);
  EXPECT_EQ(10.0f, fr->timeout);
  EXPECT_EQ(packet.message, std::get<Packet>(back).message);
}

// ---- every message ----------------------------------------------------------------

TEST(ImcMessages, EveryMessageOfTheTableRoundTrips) {
  std::set<std::uint16_t> ids;
  for (const Packet& p : testing::every_message()) {
    SCOPED_TRACE(std::string(name_of(id_of(p.message))));
    ids.insert(id_of(p.message));
    const Bytes bytes = encoded(p);
    auto back = decode(bytes);
    ASSERT_TRUE(std::holds_alternative<Packet>(back)) << drop_name(std::get<Drop>(back));
    Packet expected = p;
    expected.header.mgid = id_of(p.message);
    expected.header.size = static_cast<std::uint16_t>(bytes.size() - kHeaderBytes - kFooterBytes);
    EXPECT_EQ(expected, std::get<Packet>(back));
  }
  EXPECT_EQ(std::variant_size_v<Message>, ids.size()) << "every_message() misses a message of the table";
}

TEST(ImcMessages, IdsAndNamesAreIMCs) {
  EXPECT_EQ(350, EstimatedState::kId);
  EXPECT_EQ("EstimatedState", name_of(350));
  EXPECT_EQ("MonitorEntityState", name_of(502));
  EXPECT_TRUE(is_known(559));
  EXPECT_FALSE(is_known(450));  // Goto: not in the table
  EXPECT_FALSE(is_known(kNullId));
  EXPECT_EQ("", name_of(0));
  EXPECT_EQ("NavigationUncertainty", name_of(354));
  EXPECT_EQ(801, EntityParameter::kId);
  EXPECT_EQ("SetEntityParameters", name_of(804));
  EXPECT_EQ(24u, std::variant_size_v<Message>);
}

TEST(ImcMessages, InlineIsAValueThatOwnsItsMessage) {
  Inline a = Heartbeat{};
  Inline b = a;
  EXPECT_EQ(a, b);
  EXPECT_EQ(Heartbeat::kId, b.id());
  b = DesiredZ{3.0f, DesiredZ::kZUnitsDepth};
  EXPECT_NE(a, b);
  EXPECT_EQ(Heartbeat::kId, a.id());
  EXPECT_EQ(3.0f, b.get_if<DesiredZ>()->value);
  EXPECT_EQ(nullptr, b.get_if<Heartbeat>());
  Inline empty;
  EXPECT_TRUE(empty.empty());
  EXPECT_EQ(kNullId, empty.id());
  EXPECT_EQ(nullptr, empty.get());
  EXPECT_NE(empty, a);
  EXPECT_EQ(Inline(), empty);
}

TEST(ImcMessages, PeekHeaderReadsTheHeaderAloneForFiltering) {
  Bytes bytes = encoded(Packet{test_header(), testing::sample_estimated_state()});
  bytes.back() ^= 0xFF;  // a bad CRC: peek does not check it
  auto h = peek_header(bytes);
  ASSERT_TRUE(h.has_value());
  EXPECT_EQ(EstimatedState::kId, h->mgid);
  EXPECT_EQ(0x4001, h->src);
  EXPECT_FALSE(peek_header(Bytes(bytes.begin(), bytes.begin() + 19)).has_value());
  bytes[1] = 0x53;  // 5.3's sync
  EXPECT_FALSE(peek_header(bytes).has_value());
}

// ---- hostile datagrams -------------------------------------------------------------

// A PlanControl whose arg holds a PlanControl, `depth` times, by hand.
Bytes nested_plan_controls(int depth) {
  Bytes payload;
  for (int i = 0; i < depth; ++i) {
    payload.insert(payload.end(), {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00});  // type..flags
    payload.insert(payload.end(), {0x2F, 0x02});                                      // arg: PlanControl
  }
  payload.insert(payload.end(), {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xFF, 0xFF, 0x00, 0x00});
  for (int i = 0; i < depth; ++i) payload.insert(payload.end(), {0x00, 0x00});  // each info ""
  return datagram(559, payload);
}

TEST(ImcHostile, EachIsDroppedForItsReason) {
  const Bytes good = encoded(Packet{test_header(), testing::sample_reference()});
  DropCounts counts;
  auto expect = [&counts](Drop want, const Bytes& bytes, const char* what) {
    const Drop got = drop_of(bytes);
    EXPECT_EQ(drop_name(want), drop_name(got)) << what;
    counts.add(got);
  };

  expect(Drop::Truncated, {}, "empty");
  expect(Drop::Truncated, Bytes(good.begin(), good.begin() + 21), "shorter than header and CRC");
  expect(Drop::Truncated, Bytes(good.begin(), good.end() - 1), "a byte short of its size");
  expect(Drop::Truncated, datagram(479, {0x00}, 4000), "size says 4000");

  Bytes v53 = good;
  v53[0] = 0x53;
  expect(Drop::BadSync, v53, "IMC 5.3's sync");
  Bytes big_endian = good;
  std::swap(big_endian[0], big_endian[1]);
  expect(Drop::BadSync, big_endian, "a big-endian sender");

  Bytes longer = good;
  longer.push_back(0);
  expect(Drop::BadSize, longer, "a byte after the CRC");
  Bytes huge(kMaxPacketBytes + 1, 0x00);
  huge[0] = 0x54;
  huge[1] = 0xFE;
  expect(Drop::BadSize, huge, "over 65535 bytes");

  Bytes flipped = good;
  flipped[30] ^= 0x01;
  expect(Drop::BadCrc, flipped, "a payload bit flipped");
  Bytes crc_flipped = good;
  crc_flipped.back() ^= 0x80;
  expect(Drop::BadCrc, crc_flipped, "the CRC flipped");

  expect(Drop::UnknownId, datagram(999, {}), "an id IMC does not have");
  expect(Drop::UnknownId, datagram(254, Bytes(40, 0)), "EulerAngles: IMC's, not in the table");
  expect(Drop::UnknownId, datagram(559, {0, 0, 0, 0, 0, 0, 0, 0, 0xC2, 0x01, 0, 0}), "arg: Goto (450)");
  expect(Drop::UnknownId, datagram(551, {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0x01, 0x00, 0xE7, 0x03}),
         "maneuvers[0]: id 999");

  expect(Drop::BadField, datagram(150, {0x00}), "a byte after the last field");
  expect(Drop::BadField, datagram(1, {0x01, 0x00, 0x10, 0x00, 'a'}), "a text longer than the payload");
  expect(Drop::BadField, datagram(350, Bytes(87, 0)), "EstimatedState a byte short");
  expect(Drop::BadField, datagram(553, {0, 0, 0, 0, 0, 0, 0xFF, 0xFF, 0x96, 0x00}), "65535 actions in 2 bytes");
  expect(Drop::BadField, datagram(479, {0x02, 0x91, 0x01, 0, 0, 0, 0, 1, 0xFF, 0xFF}),
         "Reference.speed holding a DesiredZ");
  expect(Drop::BadField, datagram(551, {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0x01, 0x00, 0x96, 0x00}),
         "maneuvers[0]: a Heartbeat");

  expect(Drop::TooDeep, nested_plan_controls(9), "9 levels");
  expect(Drop::TooDeep, nested_plan_controls(4000), "4000 levels");

  EXPECT_EQ(22u, counts.total());
  EXPECT_EQ("6 bad_field, 4 truncated, 4 unknown_id, 2 bad_sync, 2 bad_size, 2 bad_crc, 2 too_deep", counts.summary());
}

// A 64 KiB PlanSpecification whose start_actions are 2,000 bare Heartbeats
// (two bytes each) would be 2,000 Message allocations for one datagram: past
// kMaxInlineMessages the packet is dropped, and encode refuses to write it.
TEST(ImcHostile, MoreInlineMessagesThanTheBudgetAreDroppedNotAllocated) {
  PlanSpecification spec;
  spec.plan_id = "p";
  for (std::size_t i = 0; i < kMaxInlineMessages; ++i) spec.start_actions.push_back(Inline(Heartbeat{}));
  ASSERT_TRUE(encode(Packet{test_header(), spec}).ok());  // at the budget: fine
  spec.start_actions.push_back(Inline(Heartbeat{}));
  auto refused = encode(Packet{test_header(), spec});
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("more than 1024 inline messages"), std::string::npos);
  // The same bytes written by hand: plan_id "p", empty texts and lists, and 2,000 Heartbeat ids.
  Bytes payload = {1, 0, 'p', 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  payload.push_back(0xD0);
  payload.push_back(0x07);  // 2,000 start actions
  for (int i = 0; i < 2000; ++i) {
    payload.push_back(0x96);
    payload.push_back(0x00);  // Heartbeat, no payload
  }
  payload.push_back(0);
  payload.push_back(0);  // no end actions
  auto result = decode(datagram(551, payload));
  ASSERT_TRUE(std::holds_alternative<Drop>(result));
  EXPECT_EQ(Drop::TooDeep, std::get<Drop>(result));
}

TEST(ImcHostile, EightLevelsOfInlineMessagesDecode) {
  auto result = decode(nested_plan_controls(8));
  ASSERT_TRUE(std::holds_alternative<Packet>(result)) << drop_name(std::get<Drop>(result));
  const Inline* arg = &std::get<PlanControl>(std::get<Packet>(result).message).arg;
  int depth = 0;
  while (const auto* pc = arg->get_if<PlanControl>()) {
    arg = &pc->arg;
    ++depth;
  }
  EXPECT_EQ(8, depth);
}

TEST(ImcHostile, EveryTruncationOfEveryMessageIsDropped) {
  for (const Packet& p : testing::every_message()) {
    const Bytes bytes = encoded(p);
    for (std::size_t n = 0; n < bytes.size(); ++n) {
      EXPECT_TRUE(std::holds_alternative<Drop>(decode(Bytes(bytes.begin(), bytes.begin() + n))));
    }
    // The payload cut short with the size and CRC made to agree.
    const std::size_t payload = bytes.size() - kHeaderBytes - kFooterBytes;
    for (std::size_t n = 0; n < payload; ++n) {
      const Bytes body(bytes.begin() + kHeaderBytes, bytes.begin() + kHeaderBytes + n);
      EXPECT_EQ(Drop::BadField, drop_of(datagram(id_of(p.message), body)))
          << name_of(id_of(p.message)) << " cut to " << n;
    }
  }
}

// ---- drop counts --------------------------------------------------------------------

TEST(ImcDropCounts, SummaryIsMostFrequentFirst) {
  DropCounts counts;
  EXPECT_EQ("none", counts.summary());
  counts.add(Drop::BadCrc);
  counts.add(Drop::Truncated);
  counts.add(Drop::BadCrc);
  counts.add(Drop::BadCrc);
  EXPECT_EQ(4u, counts.total());
  EXPECT_EQ("3 bad_crc, 1 truncated", counts.summary());
  counts.add(Drop::Filtered);
  EXPECT_EQ("3 bad_crc, 1 truncated, 1 filtered", counts.summary());
}

TEST(ImcDropCounts, NamesAreStable) {
  const char* names[] = {"truncated",  "bad_sync",  "bad_size", "bad_crc",
                         "unknown_id", "bad_field", "too_deep", "filtered"};
  for (std::size_t i = 0; i < kDropReasons; ++i) EXPECT_EQ(names[i], drop_name(static_cast<Drop>(i)));
}

// ---- what cannot be encoded ---------------------------------------------------------

TEST(ImcEncode, RefusesWhatCannotBeEncoded) {
  LogBookEntry long_text;
  long_text.text.assign(65536, 'x');
  auto a = encode(Packet{test_header(), long_text});
  ASSERT_FALSE(a.ok());
  EXPECT_EQ(core::ErrorCode::InvalidInput, a.error().code);
  EXPECT_EQ("imc: text of more than 65535 bytes", a.error().message);

  LogBookEntry too_big;
  too_big.text.assign(40000, 'x');
  too_big.context.assign(30000, 'y');
  auto b = encode(Packet{test_header(), too_big});
  ASSERT_FALSE(b.ok());
  EXPECT_EQ("imc: a packet of more than 65535 bytes", b.error().message);

  PlanControl deep;
  for (int i = 0; i < 9; ++i) {
    PlanControl outer;
    outer.arg = deep;
    deep = outer;
  }
  auto c = encode(Packet{test_header(), deep});
  ASSERT_FALSE(c.ok());
  EXPECT_EQ("imc: inline messages nested deeper than 8", c.error().message);
}

TEST(ImcEncode, SetsMgidAndSizeFromTheMessage) {
  Packet p{test_header(), Abort{}};
  p.header.mgid = 1;
  p.header.size = 99;
  auto back = decode(encoded(p));
  ASSERT_TRUE(std::holds_alternative<Packet>(back));
  EXPECT_EQ(Abort::kId, std::get<Packet>(back).header.mgid);
  EXPECT_EQ(0, std::get<Packet>(back).header.size);
}

// ---- the fuzz target -----------------------------------------------------------------

}  // namespace
}  // namespace strata::imc

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace strata::imc {
namespace {

// The target compared peek_header's header with decode's by ==, and a NaN
// timestamp is not equal to itself: it reported a codec bug that was its own.
TEST(ImcFuzzTarget, NanTimestampIsNotAMismatch) {
  Packet p{test_header(), Heartbeat{}};
  p.header.timestamp = std::numeric_limits<double>::quiet_NaN();
  const Bytes bytes = encoded(p);
  EXPECT_EQ(0, LLVMFuzzerTestOneInput(bytes.data(), bytes.size()));
}

// ---- the fuzz corpus ----------------------------------------------------------------

// fuzz/corpus/imc holds every_message() as encode() writes it (one file per
// message, named after it), so that the seeds follow the table. With
// STRATA_WRITE_IMC_CORPUS=1 in the environment this test writes them.
TEST(ImcCorpus, SeedsAreTheEncodedMessages) {
  const std::filesystem::path dir = std::filesystem::path(STRATA_SOURCE_DIR) / "fuzz" / "corpus" / "imc";
  const char* write = std::getenv("STRATA_WRITE_IMC_CORPUS");
  const bool writing = write != nullptr && std::string(write) == "1";
  if (writing) std::filesystem::create_directories(dir);
  for (const Packet& p : testing::every_message()) {
    const std::string name = std::string(name_of(id_of(p.message))) + ".imc";
    const Bytes bytes = encoded(p);
    if (writing) {
      std::ofstream(dir / name, std::ios::binary)
          .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
      continue;
    }
    std::ifstream in(dir / name, std::ios::binary);
    ASSERT_TRUE(in) << name << " missing: run imc_test with STRATA_WRITE_IMC_CORPUS=1";
    const Bytes stored((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(bytes, stored) << name << " differs from encode(): run imc_test with STRATA_WRITE_IMC_CORPUS=1";
  }
}

}  // namespace
}  // namespace strata::imc
