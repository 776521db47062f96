#include "protocol/codec.h"

#include <array>
#include <climits>
#include <cmath>
#include <span>

#include <fmt/format.h>

#include "protocol/fields.h"

namespace strata::protocol {
namespace {

template <typename... F>
struct Overloaded : F... {
  using F::operator()...;
};
template <typename... F>
Overloaded(F...) -> Overloaded<F...>;

// Telemetry's known keys, in the order they are written.
struct KnownKey {
  std::string_view key;
  std::optional<double> Telemetry::*field;
};
constexpr std::array<KnownKey, 6> kKnownKeys{{
    {"depth", &Telemetry::depth_m},
    {"fdepth", &Telemetry::filtered_depth_m},
    {"rate", &Telemetry::rate_mps},
    {"thrust", &Telemetry::thrust_n},
    {"setpoint", &Telemetry::setpoint_m},
    {"heading", &Telemetry::heading_deg},
}};

const KnownKey* find_known_key(std::string_view key) {
  for (const KnownKey& k : kKnownKeys) {
    if (k.key == key) return &k;
  }
  return nullptr;
}

bool is_key(std::string_view key) {
  if (key.empty()) return false;
  auto alpha = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; };
  if (!alpha(key[0])) return false;
  for (char c : key) {
    if (!alpha(c) && !(c >= '0' && c <= '9')) return false;
  }
  return true;
}

// ---- encoding ---------------------------------------------------------------

std::string encode_value(const Value& v) {
  switch (v.kind()) {
    case Value::Kind::Integer: return fmt::format("{}", v.as_integer());
    case Value::Kind::Float: return format_double(v.as_float());
    case Value::Kind::String: return quote(v.as_string());
  }
  return "0";
}

// `prefix "text"\n`, the text cut so that the line fits kMaxLineBytes.
std::string with_text(std::string prefix, std::string_view text) {
  std::size_t room = kMaxLineBytes > prefix.size() + 1 ? kMaxLineBytes - prefix.size() - 1 : 0;
  prefix += quote_within(text, room);
  prefix += '\n';
  return prefix;
}

std::string encode_telemetry(const Telemetry& t) {
  std::string out = fmt::format("tlm {}", format_double(t.sim_time_s));
  for (const KnownKey& k : kKnownKeys) {
    if (const std::optional<double>& v = t.*k.field) {
      out += fmt::format(" {}={}", k.key, format_double(*v));
    }
  }
  for (const auto& [key, value] : t.extras) {
    if (!is_key(key) || find_known_key(key) != nullptr || !is_bare_token(value)) continue;
    out += fmt::format(" {}={}", key, value);
  }
  out += '\n';
  return out;
}

// ---- decoding ---------------------------------------------------------------

DecodeError fail(ErrorCode code, RequestId id, std::string message) {
  return DecodeError{code, id, std::move(message)};
}

using Fields = std::span<const Field>;

// The id in the second field, 0 when there is none. Vehicle lines that carry
// no id (tlm, hb, event) have a time there instead.
RequestId id_of(Fields f, bool allow_zero = false) {
  if (f.size() < 2 || f[0].quoted || f[1].quoted) return 0;
  if (f[0].text == "tlm" || f[0].text == "hb" || f[0].text == "event") return 0;
  return parse_id(f[1].text, allow_zero).value_or(0);
}

// Strips one terminator and checks the length and the field grammar.
DecodeResult<std::vector<Field>> split(std::string_view line) {
  std::size_t terminator = 1;  // a line given without one would be sent with "\n"
  if (!line.empty() && line.back() == '\n') {
    line.remove_suffix(1);
    if (!line.empty() && line.back() == '\r') {
      line.remove_suffix(1);
      terminator = 2;
    }
  }
  if (line.size() + terminator > kMaxLineBytes) {
    return fail(ErrorCode::TooLong, peek_id(line),
                fmt::format("line of {} bytes is longer than {}", line.size() + terminator, kMaxLineBytes));
  }
  SplitResult s = split_fields(line);
  if (!s.ok()) return fail(ErrorCode::BadLine, id_of(s.fields), std::move(s.error));
  return std::move(s.fields);
}

DecodeResult<RequestId> read_id(Fields f, bool allow_zero = false) {
  if (f.size() < 2) {
    return fail(ErrorCode::BadLine, 0, fmt::format("'{}' has no id", f[0].text));
  }
  std::optional<RequestId> id;
  if (!f[1].quoted) id = parse_id(f[1].text, allow_zero);
  if (!id) {
    return fail(ErrorCode::BadLine, 0,
                fmt::format("bad id '{}': ids are integers {}..{}", f[1].text, allow_zero ? 0 : 1, kMaxRequestId));
  }
  return *id;
}

DecodeResult<std::string> read_name(const Field& f, RequestId id, std::string_view what) {
  if (f.text.empty()) return fail(ErrorCode::BadArgument, id, fmt::format("empty {}", what));
  return f.text;
}

DecodeResult<double> read_number(const Field& f, RequestId id, std::string_view what) {
  std::optional<double> d;
  if (!f.quoted) d = parse_double(f.text);
  if (!d) {
    return fail(ErrorCode::BadArgument, id, fmt::format("{} '{}' is not a finite decimal number", what, f.text));
  }
  return *d;
}

DecodeResult<double> read_time(const Field& f, RequestId id) {
  DecodeResult<double> t = read_number(f, id, "sim time");
  if (t.ok() && !(t.value() >= 0.0)) {
    return fail(ErrorCode::BadArgument, id, fmt::format("sim time '{}' is negative", f.text));
  }
  return t;
}

DecodeResult<int> read_version(const Field& f, RequestId id) {
  std::optional<RequestId> v;
  if (!f.quoted) v = parse_id(f.text);
  if (!v || *v > static_cast<RequestId>(INT_MAX)) {
    return fail(ErrorCode::BadArgument, id, fmt::format("protocol version '{}' is not a positive integer", f.text));
  }
  return static_cast<int>(*v);
}

DecodeResult<bool> read_flag(const Field& f, RequestId id) {
  if (!f.quoted && f.text == "0") return false;
  if (!f.quoted && f.text == "1") return true;
  return fail(ErrorCode::BadArgument, id, fmt::format("'{}' is not 0 or 1", f.text));
}

DecodeError wrong_arity(std::string_view verb, RequestId id, std::string_view syntax, std::size_t got) {
  return fail(ErrorCode::BadArgument, id, fmt::format("'{}' takes {} ({} fields given)", verb, syntax, got));
}

DecodeResult<Request> decode_call(Verb verb, Fields f, RequestId id) {
  std::string_view verb_text = verb_name(verb);
  if (f.size() < 3) {
    return wrong_arity(verb_text, id, verb == Verb::Ask ? "ID PREDICATE [ARG...]" : "ID FUNCTION [ARG...]", f.size());
  }
  Request r;
  r.verb = verb;
  r.id = id;
  auto name = read_name(f[2], id, verb == Verb::Ask ? "predicate" : "function");
  if (!name.ok()) return name.error();
  r.name = std::move(name).value();
  for (std::size_t i = 3; i < f.size(); ++i) {
    if (f[i].quoted) {
      r.args.push_back(Value::string(f[i].text));
      continue;
    }
    core::Result<Value> v = parse_number(f[i].text);
    if (!v.ok()) {
      return fail(ErrorCode::BadArgument, id, fmt::format("argument {}: {} (quote strings)", i - 2, v.error().message));
    }
    r.args.push_back(std::move(v).value());
  }
  return r;
}

}  // namespace

core::Error DecodeError::to_core() const {
  return core::make_error(core::ErrorCode::Protocol, fmt::format("{}: {}", code_name(code), message));
}

Err to_err(const DecodeError& e) { return Err{e.id, e.code, e.message}; }

std::string encode(const Request& r) {
  std::string out = fmt::format("{} {}", verb_name(r.verb), r.id);
  switch (r.verb) {
    case Verb::Hello: out += fmt::format(" {} {}", bare_or_quoted(r.name), r.version); break;
    case Verb::Exec:
    case Verb::Ask:
    case Verb::Ood:
      out += ' ';
      out += bare_or_quoted(r.name);
      for (const Value& v : r.args) {
        out += ' ';
        out += encode_value(v);
      }
      break;
    case Verb::Telemetry:
      out += ' ';
      out += format_double(r.rate_hz);
      break;
    case Verb::Advance:
      if (r.until_s) {
        out += ' ';
        out += format_double(*r.until_s);
      }
      break;
    case Verb::Ping:
    case Verb::Bye: break;
  }
  out += '\n';
  return out;
}

std::string encode(const VehicleMessage& message) {
  return std::visit(
      Overloaded{
          [](const Welcome& m) {
            return fmt::format("ok {} {} {} {}{}{}\n", m.id, bare_or_quoted(m.vehicle_name), m.version,
                               clock_name(m.clock), m.sonar_port ? fmt::format(" sonar={}", *m.sonar_port) : "",
                               m.sim_time_s ? fmt::format(" time={}", format_double(*m.sim_time_s)) : "");
          },
          [](const Ok& m) {
            return m.sim_time_s ? fmt::format("ok {} {}\n", m.id, format_double(*m.sim_time_s))
                                : fmt::format("ok {}\n", m.id);
          },
          [](const Done& m) {
            return fmt::format("done {} {} {}\n", m.id, m.success ? 1 : 0, format_double(m.sim_time_s));
          },
          [](const Answer& m) {
            return fmt::format("answer {} {} {}\n", m.id, m.value ? 1 : 0, format_double(m.sim_time_s));
          },
          [](const Pong& m) { return fmt::format("pong {} {}\n", m.id, format_double(m.sim_time_s)); },
          [](const Err& m) { return with_text(fmt::format("err {} {} ", m.id, code_name(m.code)), m.message); },
          [](const Telemetry& m) { return encode_telemetry(m); },
          [](const Heartbeat& m) { return fmt::format("hb {}\n", format_double(m.sim_time_s)); },
          [](const Event& m) { return with_text(fmt::format("event {} ", format_double(m.sim_time_s)), m.text); },
      },
      message);
}

DecodeResult<Request> decode_request(std::string_view line) {
  auto split_result = split(line);
  if (!split_result.ok()) return split_result.error();
  const std::vector<Field>& fields = split_result.value();
  Fields f(fields);

  static constexpr std::array<Verb, 8> kVerbs{Verb::Hello,     Verb::Exec, Verb::Ask, Verb::Ood,
                                              Verb::Telemetry, Verb::Ping, Verb::Bye, Verb::Advance};
  std::optional<Verb> verb;
  for (Verb v : kVerbs) {
    if (!f[0].quoted && f[0].text == verb_name(v)) verb = v;
  }
  if (!verb) {
    return fail(ErrorCode::UnknownVerb, id_of(f), fmt::format("unknown verb '{}'", f[0].text));
  }
  auto id_result = read_id(f);
  if (!id_result.ok()) return id_result.error();
  RequestId id = id_result.value();

  switch (*verb) {
    case Verb::Hello: {
      if (f.size() != 4) return wrong_arity("hello", id, "ID CLIENT_NAME PROTOCOL_VERSION", f.size());
      auto name = read_name(f[2], id, "client name");
      if (!name.ok()) return name.error();
      auto version = read_version(f[3], id);
      if (!version.ok()) return version.error();
      Request r = make_hello(id, std::move(name).value());
      r.version = version.value();
      return r;
    }
    case Verb::Exec:
    case Verb::Ask:
    case Verb::Ood: return decode_call(*verb, f, id);
    case Verb::Telemetry: {
      if (f.size() != 3) return wrong_arity("telemetry", id, "ID RATE_HZ", f.size());
      auto rate = read_number(f[2], id, "rate");
      if (!rate.ok()) return rate.error();
      if (!(rate.value() >= 0.0 && rate.value() <= kMaxTelemetryRateHz)) {
        return fail(ErrorCode::BadArgument, id,
                    fmt::format("rate '{}' is outside 0..{} Hz", f[2].text, kMaxTelemetryRateHz));
      }
      return make_telemetry(id, rate.value());
    }
    case Verb::Ping:
      if (f.size() != 2) return wrong_arity("ping", id, "ID only", f.size());
      return make_ping(id);
    case Verb::Bye:
      if (f.size() != 2) return wrong_arity("bye", id, "ID only", f.size());
      return make_bye(id);
    case Verb::Advance: {
      if (f.size() == 2) return make_advance(id);
      if (f.size() != 3) return wrong_arity("advance", id, "ID [UNTIL_S]", f.size());
      auto until = read_time(f[2], id);
      if (!until.ok()) return until.error();
      return make_advance(id, until.value());
    }
  }
  return fail(ErrorCode::UnknownVerb, id, "unknown verb");
}

namespace {

DecodeResult<VehicleMessage> decode_ok(Fields f, RequestId id) {
  if (f.size() == 2) return VehicleMessage{Ok{id, std::nullopt}};
  if (f.size() == 3) {
    auto time = read_time(f[2], id);
    if (!time.ok()) return time.error();
    return VehicleMessage{Ok{id, time.value()}};
  }
  if (f.size() < 5) {
    return wrong_arity("ok", id, "ID [SIM_TIME_S], or ID VEHICLE_NAME PROTOCOL_VERSION CLOCK [KEY=VALUE...]", f.size());
  }
  Welcome w;
  w.id = id;
  auto name = read_name(f[2], id, "vehicle name");
  if (!name.ok()) return name.error();
  w.vehicle_name = std::move(name).value();
  auto version = read_version(f[3], id);
  if (!version.ok()) return version.error();
  w.version = version.value();
  if (!f[4].quoted && f[4].text == "lockstep") {
    w.clock = ClockMode::Lockstep;
  } else if (!f[4].quoted && f[4].text == "wall") {
    w.clock = ClockMode::Wall;
  } else {
    return fail(ErrorCode::BadArgument, id, fmt::format("clock '{}' is neither lockstep nor wall", f[4].text));
  }
  for (std::size_t i = 5; i < f.size(); ++i) {
    const std::string_view field = f[i].text;
    const auto eq = field.find('=');
    if (f[i].quoted || eq == std::string_view::npos || eq == 0) {
      return fail(ErrorCode::BadArgument, id, fmt::format("'{}' after the clock is not KEY=VALUE", field));
    }
    const std::string_view key = field.substr(0, eq);
    if (key == "time") {
      auto time = read_time(Field{std::string(field.substr(eq + 1)), false}, id);
      if (!time.ok()) return time.error();
      w.sim_time_s = time.value();
      continue;
    }
    if (key != "sonar") continue;  // a later version's: ignored
    const std::string value(field.substr(eq + 1));
    char* end = nullptr;
    const unsigned long port = std::strtoul(value.c_str(), &end, 10);
    if (value.empty() || *end != '\0' || port == 0 || port > 65535) {
      return fail(ErrorCode::BadArgument, id, fmt::format("sonar port '{}' is not a port (1 to 65535)", value));
    }
    w.sonar_port = static_cast<std::uint16_t>(port);
  }
  return VehicleMessage{std::move(w)};
}

DecodeResult<VehicleMessage> decode_tlm(Fields f) {
  if (f.size() < 2) return wrong_arity("tlm", 0, "SIM_TIME_S [KEY=VALUE...]", f.size());
  Telemetry t;
  auto time = read_time(f[1], 0);
  if (!time.ok()) return time.error();
  t.sim_time_s = time.value();
  std::vector<std::string_view> seen;
  for (std::size_t i = 2; i < f.size(); ++i) {
    std::string_view field = f[i].text;
    std::size_t eq = field.find('=');
    if (f[i].quoted || eq == std::string_view::npos || !is_key(field.substr(0, eq)) || eq + 1 == field.size()) {
      return fail(ErrorCode::BadArgument, 0, fmt::format("'{}' is not KEY=VALUE", field));
    }
    std::string_view key = field.substr(0, eq);
    std::string_view value = field.substr(eq + 1);
    for (std::string_view s : seen) {
      if (s == key) return fail(ErrorCode::BadArgument, 0, fmt::format("key '{}' repeated", key));
    }
    seen.push_back(key);
    if (const KnownKey* k = find_known_key(key)) {
      std::optional<double> d = parse_double(value);
      if (!d) {
        return fail(ErrorCode::BadArgument, 0, fmt::format("{} '{}' is not a finite decimal number", key, value));
      }
      t.*(k->field) = *d;
    } else {
      t.extras.emplace(std::string(key), std::string(value));
    }
  }
  return VehicleMessage{std::move(t)};
}

}  // namespace

DecodeResult<VehicleMessage> decode_vehicle_message(std::string_view line) {
  auto split_result = split(line);
  if (!split_result.ok()) return split_result.error();
  const std::vector<Field>& fields = split_result.value();
  Fields f(fields);
  std::string_view verb = f[0].quoted ? std::string_view() : std::string_view(f[0].text);

  if (verb == "tlm") return decode_tlm(f);
  if (verb == "hb" || verb == "event") {
    std::size_t want = verb == "hb" ? 2 : 3;
    if (f.size() != want) {
      return wrong_arity(verb, 0, verb == "hb" ? "SIM_TIME_S" : "SIM_TIME_S \"TEXT\"", f.size());
    }
    auto time = read_time(f[1], 0);
    if (!time.ok()) return time.error();
    if (verb == "hb") return VehicleMessage{Heartbeat{time.value()}};
    return VehicleMessage{Event{time.value(), f[2].text}};
  }
  if (verb != "ok" && verb != "done" && verb != "answer" && verb != "pong" && verb != "err") {
    return fail(ErrorCode::UnknownVerb, id_of(f, true), fmt::format("unknown verb '{}'", f[0].text));
  }
  auto id_result = read_id(f, verb == "err");
  if (!id_result.ok()) return id_result.error();
  RequestId id = id_result.value();

  if (verb == "ok") return decode_ok(f, id);
  if (verb == "done" || verb == "answer") {
    if (f.size() != 4) return wrong_arity(verb, id, "ID 0|1 SIM_TIME_S", f.size());
    auto flag = read_flag(f[2], id);
    if (!flag.ok()) return flag.error();
    auto time = read_time(f[3], id);
    if (!time.ok()) return time.error();
    if (verb == "done") return VehicleMessage{Done{id, flag.value(), time.value()}};
    return VehicleMessage{Answer{id, flag.value(), time.value()}};
  }
  if (verb == "pong") {
    if (f.size() != 3) return wrong_arity(verb, id, "ID SIM_TIME_S", f.size());
    auto time = read_time(f[2], id);
    if (!time.ok()) return time.error();
    return VehicleMessage{Pong{id, time.value()}};
  }
  // err
  if (f.size() != 4) return wrong_arity(verb, id, "ID CODE \"MESSAGE\"", f.size());
  std::optional<ErrorCode> code;
  if (!f[2].quoted) code = parse_error_code(f[2].text);
  if (!code) return fail(ErrorCode::BadArgument, id, fmt::format("unknown error code '{}'", f[2].text));
  return VehicleMessage{Err{id, *code, f[3].text}};
}

RequestId peek_id(std::string_view line) {
  SplitResult s = split_fields(line);
  return id_of(s.fields);
}

}  // namespace strata::protocol
