// The codec's properties (rapidcheck): any EstimatedState, Reference,
// VehicleState or PlanControl survives encode -> decode, and decoding any
// bytes, or any corruption of a valid packet, gives a packet or a drop.
// The examples are codec_test.cpp.
#include <cstring>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include "imc/codec.h"
#include "imc/codec_test_support.h"

namespace strata::imc {
namespace {

namespace gen = rc::gen;

// Any bit pattern is a float or double the codec must carry (NaNs too):
// values are compared by their encodings, which NaN != NaN cannot upset.
template <typename T>
rc::Gen<T> any_bits() {
  using Bits = std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>;
  return gen::map(gen::arbitrary<Bits>(), [](Bits b) {
    T v;
    std::memcpy(&v, &b, sizeof v);
    return v;
  });
}

rc::Gen<std::string> short_texts() { return gen::container<std::string>(gen::inRange<char>(0, 127)); }

rc::Gen<Header> headers() {
  return gen::apply(
      [](double t, std::uint16_t src, std::uint8_t src_ent, std::uint16_t dst, std::uint8_t dst_ent) {
        Header h;
        h.timestamp = t;
        h.src = src;
        h.src_ent = src_ent;
        h.dst = dst;
        h.dst_ent = dst_ent;
        return h;
      },
      any_bits<double>(), gen::arbitrary<std::uint16_t>(), gen::arbitrary<std::uint8_t>(),
      gen::arbitrary<std::uint16_t>(), gen::arbitrary<std::uint8_t>());
}

rc::Gen<EstimatedState> estimated_states() {
  return gen::map(gen::container<std::vector<float>>(18, any_bits<float>()), [](const std::vector<float>& f) {
    EstimatedState s;
    s.lat = static_cast<double>(f[0]) * 1e-3;
    s.lon = static_cast<double>(f[1]) * 1e-3;
    float* fields[] = {&s.height, &s.x,  &s.y,  &s.z,  &s.phi, &s.theta, &s.psi, &s.u,     &s.v,
                       &s.w,      &s.vx, &s.vy, &s.vz, &s.p,   &s.q,     &s.r,   &s.depth, &s.alt};
    for (std::size_t i = 0; i < 18; ++i) *fields[i] = f[i];
    return s;
  });
}

rc::Gen<Reference> references() {
  return gen::apply(
      [](std::uint8_t flags, rc::Maybe<double> speed, rc::Maybe<float> z, double lat, double lon, float radius) {
        Reference r;
        r.flags = flags;
        if (speed) r.speed = DesiredSpeed{*speed, DesiredSpeed::kSpeedUnitsMetersPs};
        if (z) r.z = DesiredZ{*z, DesiredZ::kZUnitsDepth};
        r.lat = lat;
        r.lon = lon;
        r.radius = radius;
        return r;
      },
      gen::arbitrary<std::uint8_t>(), gen::maybe(any_bits<double>()), gen::maybe(any_bits<float>()), any_bits<double>(),
      any_bits<double>(), any_bits<float>());
}

rc::Gen<VehicleState> vehicle_states() {
  return gen::apply(
      [](std::uint8_t mode, std::string ents, std::uint32_t loops, std::string last) {
        VehicleState v;
        v.op_mode = mode;
        v.error_ents = std::move(ents);
        v.control_loops = loops;
        v.last_error = std::move(last);
        return v;
      },
      gen::arbitrary<std::uint8_t>(), short_texts(), gen::arbitrary<std::uint32_t>(), short_texts());
}

rc::Gen<PlanControl> plan_controls() {
  return gen::apply(
      [](std::uint16_t request_id, std::string plan_id, Reference r, bool with_plan, std::string info) {
        PlanControl pc = testing::follow_reference_plan();
        pc.request_id = request_id;
        pc.plan_id = std::move(plan_id);
        pc.info = std::move(info);
        if (!with_plan) pc.arg = r;
        return pc;
      },
      gen::arbitrary<std::uint16_t>(), short_texts(), references(), gen::arbitrary<bool>(), short_texts());
}

// encode -> decode -> encode gives the same bytes, and the decoded header
// is the one sent (with mgid and size filled in).
void check_round_trip(const Packet& p) {
  auto bytes = encode(p);
  RC_ASSERT(bytes.ok());
  auto back = decode(bytes.value());
  RC_ASSERT(std::holds_alternative<Packet>(back));
  const Packet& q = std::get<Packet>(back);
  RC_ASSERT(q.header.mgid == id_of(p.message));
  RC_ASSERT(q.message.index() == p.message.index());
  auto again = encode(q);
  RC_ASSERT(again.ok());
  RC_ASSERT(again.value() == bytes.value());
}

RC_GTEST_PROP(ImcProperties, EstimatedStateRoundTrips, ()) {
  check_round_trip(Packet{*headers(), *estimated_states()});
}

RC_GTEST_PROP(ImcProperties, ReferenceRoundTrips, ()) { check_round_trip(Packet{*headers(), *references()}); }

RC_GTEST_PROP(ImcProperties, VehicleStateRoundTrips, ()) { check_round_trip(Packet{*headers(), *vehicle_states()}); }

RC_GTEST_PROP(ImcProperties, PlanControlRoundTrips, ()) { check_round_trip(Packet{*headers(), *plan_controls()}); }

RC_GTEST_PROP(ImcProperties, AnyBytesDecodeToAPacketOrADrop, (const std::vector<std::uint8_t>& bytes)) {
  auto result = decode(bytes);
  RC_ASSERT(result.index() <= 1u);
}

// A valid packet with bytes overwritten and its CRC made right again (so
// that the damage reaches the fields): a packet or a drop, and a packet
// re-encodes to the very bytes it came from.
RC_GTEST_PROP(ImcProperties, CorruptedPayloadsAreSafe, ()) {
  const auto messages = testing::every_message();
  const Packet& p = messages[*gen::inRange<std::size_t>(0, messages.size())];
  std::vector<std::uint8_t> bytes = encode(p).value();
  bytes.resize(bytes.size() - kFooterBytes);
  const auto edits = *gen::container<std::vector<std::pair<std::size_t, std::uint8_t>>>(
      gen::pair(gen::inRange<std::size_t>(kHeaderBytes, bytes.size() + 1), gen::arbitrary<std::uint8_t>()));
  for (const auto& [at, value] : edits) {
    if (at < bytes.size()) bytes[at] = value;
  }
  bytes = testing::with_crc(bytes);
  auto result = decode(bytes);
  if (const auto* q = std::get_if<Packet>(&result)) {
    auto again = encode(*q);
    RC_ASSERT(again.ok());
    RC_ASSERT(again.value() == bytes);
  }
}

}  // namespace
}  // namespace strata::imc
