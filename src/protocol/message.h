#pragma once
// The wire messages of the protocol (versions 1 and 2) as plain values:
// requests from the tactical client to the vehicle, and every line the
// vehicle sends back. codec.h turns them into lines and back;
// docs/protocol.md is the table.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace strata::protocol {

// The newest version, what a client says in hello unless told otherwise.
// Version 2 adds `advance` (docs/protocol.md §8): in lockstep, time moves
// only on it, so requests in flight together share simulated time. Version 1
// is version 2 without `advance`: in lockstep each request moves time itself.
inline constexpr int kProtocolVersion = 2;
// The oldest version this code still speaks (both ends).
inline constexpr int kOldestProtocolVersion = 1;
// Whether this code speaks `version`; "1 and 2" for messages.
bool speaks_version(int version);
std::string spoken_versions();
// One line, its "\n" (or "\r\n") included.
inline constexpr std::size_t kMaxLineBytes = 1024;
// Fields on one line, the verb included.
inline constexpr std::size_t kMaxFields = 64;
inline constexpr double kMaxTelemetryRateHz = 100.0;

// Chosen by the client, unique among its requests in flight, 1..kMaxRequestId.
// 0 appears only in `err 0 ...`: the offending line had no readable id.
using RequestId = std::uint64_t;
inline constexpr RequestId kMaxRequestId = std::numeric_limits<std::int64_t>::max();

// The CODE of an `err` line.
enum class ErrorCode {
  BadLine,          // bad_line: not a well-formed line, or no readable id
  TooLong,          // too_long: longer than kMaxLineBytes
  UnknownVerb,      // unknown_verb
  BadArgument,      // bad_argument: wrong number or kind of fields after the id
  UnknownFunction,  // unknown_function: not in the vehicle's table
  Busy,             // busy: another client is in control
  NotReady,         // not_ready: e.g. a request before hello
  Failed,           // failed: the function could not be run
  DuplicateId,      // duplicate_id: the id is already in flight
};
std::string_view code_name(ErrorCode code);
std::optional<ErrorCode> parse_error_code(std::string_view name);

// A literal argument of exec/ask/ood. Integers and floats stay distinct so
// that `sleep 1` and `sleep 1.0` both round-trip as written.
class Value {
 public:
  enum class Kind { Integer, Float, String };

  Value() : v_(std::int64_t{0}) {}
  static Value integer(std::int64_t i) { return Value(i); }
  static Value real(double d) { return Value(d); }  // d must be finite to be encoded
  static Value string(std::string s) { return Value(std::move(s)); }

  Kind kind() const { return static_cast<Kind>(v_.index()); }
  bool is_number() const { return kind() != Kind::String; }
  // Integer or float as a double; nullopt for a string.
  std::optional<double> number() const;
  std::int64_t as_integer() const { return std::get<std::int64_t>(v_); }
  double as_float() const { return std::get<double>(v_); }
  const std::string& as_string() const { return std::get<std::string>(v_); }

  friend bool operator==(const Value&, const Value&) = default;

 private:
  explicit Value(std::int64_t i) : v_(i) {}
  explicit Value(double d) : v_(d) {}
  explicit Value(std::string s) : v_(std::move(s)) {}
  std::variant<std::int64_t, double, std::string> v_;
};

enum class Verb { Hello, Exec, Ask, Ood, Telemetry, Ping, Bye, Advance };
std::string_view verb_name(Verb verb);

// Client -> vehicle. Which fields matter depends on the verb:
//   Hello:          name = client name, version
//   Exec, Ood:      name = function, args
//   Ask:            name = predicate, args
//   Telemetry:      rate_hz (0 stops)
//   Ping, Bye:      id only
//   Advance:        id, until_s (protocol 2: the client has issued everything
//                   for the current simulated instant; the vehicle may move
//                   time, in lockstep no further than until_s if given)
struct Request {
  Verb verb = Verb::Ping;
  RequestId id = 1;
  std::string name;
  std::vector<Value> args;
  int version = kProtocolVersion;
  double rate_hz = 0.0;
  std::optional<double> until_s;  // advance: the latest simulated time to step to

  friend bool operator==(const Request&, const Request&) = default;
};

Request make_hello(RequestId id, std::string client_name);
Request make_exec(RequestId id, std::string function, std::vector<Value> args = {});
Request make_ask(RequestId id, std::string predicate, std::vector<Value> args = {});
Request make_ood(RequestId id, std::string function, std::vector<Value> args = {});
Request make_telemetry(RequestId id, double rate_hz);
Request make_ping(RequestId id);
Request make_bye(RequestId id);
Request make_advance(RequestId id, std::optional<double> until_s = std::nullopt);

enum class ClockMode { Lockstep, Wall };
std::string_view clock_name(ClockMode clock);

// Vehicle -> client. Replies carry the id of their request.

// `ok ID VEHICLE_NAME VERSION CLOCK [sonar=PORT] [KEY=VALUE...]`: the reply
// to hello. VERSION is the session's: the version the hello asked for (a
// version-1 vehicle says 1 whatever it was asked). sonar= is the vehicle's
// sonar socket (docs/protocol.md §10); other KEY=VALUE fields are for later
// versions and are ignored.
struct Welcome {
  RequestId id = 1;
  std::string vehicle_name;
  int version = kProtocolVersion;
  ClockMode clock = ClockMode::Lockstep;
  std::optional<std::uint16_t> sonar_port;
  std::optional<double> sim_time_s;  // time=: the vehicle's simulated time at the hello
  friend bool operator==(const Welcome&, const Welcome&) = default;
};
// `ok ID [SIM_TIME_S]`: the reply to telemetry, bye and advance. An advance
// that names a time (`advance ID UNTIL_S`) is answered with the vehicle's
// simulated time when it ends.
struct Ok {
  RequestId id = 1;
  std::optional<double> sim_time_s;
  friend bool operator==(const Ok&, const Ok&) = default;
};
// `done ID 0|1 SIM_TIME_S`: the reply to exec and ood; success = the function
// executed; the vehicle's simulated time when it replied.
struct Done {
  RequestId id = 1;
  bool success = false;
  double sim_time_s = 0.0;
  friend bool operator==(const Done&, const Done&) = default;
};
// `answer ID 0|1 SIM_TIME_S`: the reply to ask, and the simulated time it holds for.
struct Answer {
  RequestId id = 1;
  bool value = false;
  double sim_time_s = 0.0;
  friend bool operator==(const Answer&, const Answer&) = default;
};
// `pong ID SIM_TIME_S`: the reply to ping.
struct Pong {
  RequestId id = 1;
  double sim_time_s = 0.0;
  friend bool operator==(const Pong&, const Pong&) = default;
};
// `err ID CODE "MESSAGE"`: the reply to a request that could not be taken;
// id 0 when the offending line had no readable id.
struct Err {
  RequestId id = 0;
  ErrorCode code = ErrorCode::BadLine;
  std::string message;
  friend bool operator==(const Err&, const Err&) = default;
};
// `tlm SIM_TIME_S depth=M fdepth=M rate=MPS thrust=N setpoint=M heading=DEG [key=value...]`.
// A known key the vehicle has no value for yet is left out of the line (fdepth
// and rate before the depth filter runs, setpoint before one is set). Keys this
// version does not know are kept in `extras` with their raw value text.
struct Telemetry {
  double sim_time_s = 0.0;
  std::optional<double> depth_m;           // depth= : the depth cell, metres, down positive
  std::optional<double> filtered_depth_m;  // fdepth= : the depth filter's estimate
  std::optional<double> rate_mps;          // rate= : the filter's depth rate, m/s, down positive
  std::optional<double> thrust_n;          // thrust= : total vertical thrust, N, down positive
  std::optional<double> setpoint_m;        // setpoint= : the depth law's set point
  std::optional<double> heading_deg;       // heading= : compass heading of the bow, degrees
  std::map<std::string, std::string> extras;
  friend bool operator==(const Telemetry&, const Telemetry&) = default;
};
// `hb SIM_TIME_S`: the vehicle is alive.
struct Heartbeat {
  double sim_time_s = 0.0;
  friend bool operator==(const Heartbeat&, const Heartbeat&) = default;
};
// `event SIM_TIME_S "TEXT"`: one of the vehicle's own log lines.
struct Event {
  double sim_time_s = 0.0;
  std::string text;
  friend bool operator==(const Event&, const Event&) = default;
};

using VehicleMessage = std::variant<Welcome, Ok, Done, Answer, Pong, Err, Telemetry, Heartbeat, Event>;

// The id a vehicle message answers; nullopt for tlm, hb and event.
std::optional<RequestId> reply_id(const VehicleMessage& message);

}  // namespace strata::protocol
