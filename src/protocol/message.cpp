#include "protocol/message.h"

#include <array>
#include <type_traits>
#include <utility>

namespace strata::protocol {
namespace {

constexpr std::array<std::pair<ErrorCode, std::string_view>, 9> kCodeNames{{
    {ErrorCode::BadLine, "bad_line"},
    {ErrorCode::TooLong, "too_long"},
    {ErrorCode::UnknownVerb, "unknown_verb"},
    {ErrorCode::BadArgument, "bad_argument"},
    {ErrorCode::UnknownFunction, "unknown_function"},
    {ErrorCode::Busy, "busy"},
    {ErrorCode::NotReady, "not_ready"},
    {ErrorCode::Failed, "failed"},
    {ErrorCode::DuplicateId, "duplicate_id"},
}};

}  // namespace

std::string_view code_name(ErrorCode code) {
  for (const auto& [c, name] : kCodeNames) {
    if (c == code) return name;
  }
  return "bad_line";
}

std::optional<ErrorCode> parse_error_code(std::string_view name) {
  for (const auto& [c, n] : kCodeNames) {
    if (n == name) return c;
  }
  return std::nullopt;
}

std::optional<double> Value::number() const {
  switch (kind()) {
    case Kind::Integer: return static_cast<double>(as_integer());
    case Kind::Float: return as_float();
    case Kind::String: return std::nullopt;
  }
  return std::nullopt;
}

std::string_view verb_name(Verb verb) {
  switch (verb) {
    case Verb::Hello: return "hello";
    case Verb::Exec: return "exec";
    case Verb::Ask: return "ask";
    case Verb::Ood: return "ood";
    case Verb::Telemetry: return "telemetry";
    case Verb::Ping: return "ping";
    case Verb::Bye: return "bye";
    case Verb::Advance: return "advance";
  }
  return "?";
}

std::string_view clock_name(ClockMode clock) { return clock == ClockMode::Lockstep ? "lockstep" : "wall"; }

Request make_hello(RequestId id, std::string client_name) {
  Request r;
  r.verb = Verb::Hello;
  r.id = id;
  r.name = std::move(client_name);
  return r;
}

namespace {
Request make_call(Verb verb, RequestId id, std::string name, std::vector<Value> args) {
  Request r;
  r.verb = verb;
  r.id = id;
  r.name = std::move(name);
  r.args = std::move(args);
  return r;
}
}  // namespace

Request make_exec(RequestId id, std::string function, std::vector<Value> args) {
  return make_call(Verb::Exec, id, std::move(function), std::move(args));
}
Request make_ask(RequestId id, std::string predicate, std::vector<Value> args) {
  return make_call(Verb::Ask, id, std::move(predicate), std::move(args));
}
Request make_ood(RequestId id, std::string function, std::vector<Value> args) {
  return make_call(Verb::Ood, id, std::move(function), std::move(args));
}

Request make_telemetry(RequestId id, double rate_hz) {
  Request r;
  r.verb = Verb::Telemetry;
  r.id = id;
  r.rate_hz = rate_hz;
  return r;
}

Request make_ping(RequestId id) {
  Request r;
  r.verb = Verb::Ping;
  r.id = id;
  return r;
}

Request make_bye(RequestId id) {
  Request r;
  r.verb = Verb::Bye;
  r.id = id;
  return r;
}

Request make_advance(RequestId id, std::optional<double> until_s) {
  Request r;
  r.verb = Verb::Advance;
  r.id = id;
  r.until_s = until_s;
  return r;
}

bool speaks_version(int version) { return version >= kOldestProtocolVersion && version <= kProtocolVersion; }

std::string spoken_versions() {
  std::string out;
  for (int v = kOldestProtocolVersion; v <= kProtocolVersion; ++v) {
    if (!out.empty()) out += v == kProtocolVersion ? " and " : ", ";
    out += std::to_string(v);
  }
  return out;
}

std::optional<RequestId> reply_id(const VehicleMessage& message) {
  return std::visit(
      [](const auto& m) -> std::optional<RequestId> {
        using M = std::decay_t<decltype(m)>;
        if constexpr (std::is_same_v<M, Telemetry> || std::is_same_v<M, Heartbeat> || std::is_same_v<M, Event>) {
          return std::nullopt;
        } else {
          return m.id;
        }
      },
      message);
}

}  // namespace strata::protocol
