// The codec's properties (rapidcheck): every request and vehicle message
// round-trips through its wire line, any free text makes a valid line, and
// decoding arbitrary bytes is safe. The examples are codec_test.cpp.
#include <cmath>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include "protocol/codec.h"

namespace strata::protocol {

// rapidcheck shows counterexamples as their wire form.
void showValue(const Request& r, std::ostream& os) { os << encode(r); }
void showValue(const VehicleMessage& m, std::ostream& os) { os << encode(m); }

namespace {

namespace gen = rc::gen;

// ---- properties ---------------------------------------------------------------

rc::Gen<RequestId> ids() {
  return gen::oneOf(gen::inRange<RequestId>(1, kMaxRequestId),
                    gen::element<RequestId>(1, 2, kMaxRequestId - 1, kMaxRequestId));
}

// Text the grammar carries unchanged: printable ASCII, newline and tab.
rc::Gen<std::string> texts(int max_length) {
  auto chars = gen::weightedOneOf<char>({
      {8, gen::inRange<char>(0x20, 0x7f)},
      {1, gen::element('"', '\\', '\n', '\t', ' ')},
  });
  return gen::mapcat(gen::inRange(0, max_length + 1),
                     [chars](int n) { return gen::container<std::string>(static_cast<std::size_t>(n), chars); });
}

rc::Gen<std::string> names() {
  return gen::oneOf(gen::element<std::string>("sleep", "setpoint", "depth_reached", "phoenix"),
                    gen::nonEmpty(texts(24)));
}

rc::Gen<double> finite_doubles() {
  return gen::oneOf(gen::suchThat(gen::arbitrary<double>(), [](double d) { return std::isfinite(d); }),
                    gen::element(0.0, -0.0, 0.6, 1.0, 1e300, 5e-324, -2.5e-3));
}

rc::Gen<double> times() {
  return gen::map(finite_doubles(), [](double d) { return std::fabs(d); });
}

rc::Gen<std::optional<double>> maybe_clock_times() {
  return gen::oneOf(gen::just(std::optional<double>()),
                    gen::map(times(), [](double d) { return std::optional<double>(d); }));
}

rc::Gen<Value> values() {
  return gen::oneOf(gen::map(gen::arbitrary<std::int64_t>(), Value::integer), gen::map(finite_doubles(), Value::real),
                    gen::map(texts(24), Value::string));
}

rc::Gen<Request> requests() {
  auto call = [](Verb verb) {
    return gen::apply(
        [verb](RequestId id, std::string name, std::vector<Value> args) {
          Request r = make_exec(id, std::move(name), std::move(args));
          r.verb = verb;
          return r;
        },
        ids(), names(), gen::mapcat(gen::inRange(0, 9), [](int n) {
          return gen::container<std::vector<Value>>(static_cast<std::size_t>(n), values());
        }));
  };
  return gen::oneOf(gen::apply(
                        [](RequestId id, std::string name, int version) {
                          Request r = make_hello(id, std::move(name));
                          r.version = version;
                          return r;
                        },
                        ids(), names(), gen::inRange(1, 1 << 30)),
                    call(Verb::Exec), call(Verb::Ask), call(Verb::Ood),
                    gen::apply(make_telemetry, ids(),
                               gen::oneOf(gen::element(0.0, 1.0, 2.5, kMaxTelemetryRateHz),
                                          gen::map(gen::inRange(0, 1 << 20),
                                                   [](int i) { return kMaxTelemetryRateHz * i / (1 << 20); }))),
                    gen::map(ids(), make_ping), gen::map(ids(), make_bye),
                    gen::apply([](RequestId id, std::optional<double> until) { return make_advance(id, until); }, ids(),
                               maybe_clock_times()));
}

rc::Gen<std::optional<double>> maybe_times() {
  return gen::oneOf(gen::just(std::optional<double>()),
                    gen::map(finite_doubles(), [](double d) { return std::optional<double>(d); }));
}

rc::Gen<std::map<std::string, std::string>> extras() {
  auto key = gen::element<std::string>("mode", "leak", "battery_v", "x_1", "_k");
  auto value =
      gen::nonEmpty(gen::container<std::string>(gen::element('a', 'Z', '0', '9', '_', '.', ':', '+', '-', '/', '=')));
  return gen::container<std::map<std::string, std::string>>(key, value);
}

rc::Gen<VehicleMessage> vehicle_messages() {
  auto as_message = [](auto g) { return gen::map(std::move(g), [](auto m) { return VehicleMessage(std::move(m)); }); };
  auto codes = gen::element(ErrorCode::BadLine, ErrorCode::TooLong, ErrorCode::UnknownVerb, ErrorCode::BadArgument,
                            ErrorCode::UnknownFunction, ErrorCode::Busy, ErrorCode::NotReady, ErrorCode::Failed,
                            ErrorCode::DuplicateId);
  return gen::oneOf(
      as_message(gen::apply(
          [](RequestId id, std::string name, int version, bool wall) {
            return Welcome{id,           std::move(name), version, wall ? ClockMode::Wall : ClockMode::Lockstep,
                           std::nullopt, std::nullopt};
          },
          ids(), names(), gen::inRange(1, 1 << 30), gen::arbitrary<bool>())),
      as_message(gen::apply(
          [](RequestId id, std::optional<double> t) {
            return Ok{id, t};
          },
          ids(), maybe_clock_times())),
      as_message(gen::apply(
          [](RequestId id, bool b, double t) {
            return Done{id, b, t};
          },
          ids(), gen::arbitrary<bool>(), times())),
      as_message(gen::apply(
          [](RequestId id, bool b, double t) {
            return Answer{id, b, t};
          },
          ids(), gen::arbitrary<bool>(), times())),
      as_message(gen::apply(
          [](RequestId id, double t) {
            return Pong{id, t};
          },
          ids(), times())),
      as_message(gen::apply(
          [](RequestId id, ErrorCode code, std::string text) {
            return Err{id, code, std::move(text)};
          },
          gen::oneOf(ids(), gen::just<RequestId>(0)), codes, texts(200))),
      as_message(gen::apply(
          [](double t, std::optional<double> a, std::optional<double> b, std::optional<double> c,
             std::optional<double> d, std::optional<double> e, std::optional<double> h,
             std::map<std::string, std::string> x) { return Telemetry{t, a, b, c, d, e, h, std::move(x)}; },
          times(), maybe_times(), maybe_times(), maybe_times(), maybe_times(), maybe_times(), maybe_times(), extras())),
      as_message(gen::map(times(), [](double t) { return Heartbeat{t}; })),
      as_message(gen::apply(
          [](double t, std::string s) {
            return Event{t, std::move(s)};
          },
          times(), texts(200))));
}

// A valid line: printable ASCII, one "\n" at the end, within the limit.
bool is_wire_line(const std::string& line) {
  if (line.empty() || line.size() > kMaxLineBytes || line.back() != '\n') return false;
  for (std::size_t i = 0; i + 1 < line.size(); ++i) {
    if (line[i] < 0x20 || line[i] > 0x7e) return false;
  }
  return true;
}

RC_GTEST_PROP(Codec, EveryRequestRoundTrips, ()) {
  const Request r = *requests();
  const std::string line = encode(r);
  RC_ASSERT(is_wire_line(line));
  auto back = decode_request(line);
  RC_ASSERT(back.ok());
  RC_ASSERT(back.value() == r);
}

RC_GTEST_PROP(Codec, EveryVehicleMessageRoundTrips, ()) {
  const VehicleMessage m = *vehicle_messages();
  const std::string line = encode(m);
  RC_ASSERT(is_wire_line(line));
  auto back = decode_vehicle_message(line);
  RC_ASSERT(back.ok());
  RC_ASSERT(back.value() == m);
}

// Free text of any bytes and length still makes a line the other end reads.
RC_GTEST_PROP(Codec, AnyFreeTextMakesAValidLine, (const std::string& text, RequestId id)) {
  for (const VehicleMessage& m : {VehicleMessage(Err{id % (kMaxRequestId + 1), ErrorCode::Failed, text + text + text}),
                                  VehicleMessage(Event{1.5, text})}) {
    const std::string line = encode(m);
    RC_ASSERT(is_wire_line(line));
    RC_ASSERT(decode_vehicle_message(line).ok());
  }
}

// Any accepted line has one canonical form that decodes to the same request.
RC_GTEST_PROP(Codec, DecodingArbitraryBytesIsSafeAndCanonical, ()) {
  const std::string line = *gen::oneOf(
      gen::arbitrary<std::string>(), gen::map(requests(), [](const Request& r) { return encode(r); }),
      gen::apply([](std::string a, std::string b) { return a + " " + b; },
                 gen::element<std::string>("exec 1", "ask 2 x", "hello 3", "telemetry 4"),
                 gen::container<std::string>(gen::element('1', '.', 'e', '-', ' ', '"', '\\', 'n', 'a', '='))));
  auto r = decode_request(line);
  if (r.ok()) {
    auto again = decode_request(encode(r.value()));
    RC_ASSERT(again.ok());
    RC_ASSERT(again.value() == r.value());
  } else {
    RC_ASSERT(!r.error().message.empty());
    RC_ASSERT(r.error().id <= kMaxRequestId);
  }
  auto m = decode_vehicle_message(line);
  if (m.ok()) RC_ASSERT(decode_vehicle_message(encode(m.value())).value() == m.value());
}

}  // namespace
}  // namespace strata::protocol
