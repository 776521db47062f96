#pragma once
// The vehicle primitive catalogue (docs/protocol.md, docs/language.md §7): every primitive the
// Strategic level may call, its arguments with units, its reply timeout and
// the script message it sends. The catalogue is data: config/primitives.toml
// is compiled into the library (Catalogue::builtin()); a vehicle with other
// primitives brings its own file (Catalogue::load()). The format is described
// at the top of config/primitives.toml.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/call_verb.h"
#include "core/result.h"
#include "tactical/message_template.h"
#include "tactical/value.h"

namespace strata::tactical {

// A primitive's kind is its call verb: "exec", "ask", "ood", "report" in
// the catalogue file, spelled by core::call_verb_name().
using Kind = core::CallVerb;

// Where the Tactical level takes a primitive's data from, beside its arguments.
enum class DataSource {
  None,
  Setpoint,  // each call advances the mission data cursor; {depth_m}, {timeout_s}
  Waypoint,  // each call advances the waypoint cursor; {x_m}, {y_m}
};

struct Argument {
  std::string name;
  Value::Type type = Value::Type::Number;
  std::string unit;                    // "s", "m", ...; "" for none
  std::optional<double> min;           // inclusive; numbers only
  std::optional<double> max;           // inclusive; numbers only
  std::optional<Value> default_value;  // set: the argument may be left out
};

struct Primitive {
  std::string name;  // as written in CORAL
  Kind kind = Kind::Exec;
  std::vector<Argument> args;
  double timeout_s = 0;  // the reply timeout, s; 0 for report
  // The Execution level's promise: it answers within this (after the
  // timeout_plus_arg argument, for sleep), s. The timing analysis
  // (`strata verify --bound`) uses it; nullopt: the catalogue's reply_s.
  std::optional<double> reply_s;
  std::string doc;
  std::string message;           // the template, e.g. "exec sleep {seconds}"; "" for report
  std::string timeout_plus_arg;  // an argument in seconds added to timeout_s; "" if none
  DataSource data = DataSource::None;
  std::uint32_t line = 0;  // where the [[primitive]] table starts in its file

  std::size_t min_args() const;  // arguments without a default
  std::size_t max_args() const { return args.size(); }
  const Argument* find_arg(std::string_view arg_name) const;
  // How PROLOG calls it: "exec_sleep/2", "ask_time_out/1", "ood/2", "report/1".
  std::string prolog_predicate() const;
  // The call as a rule writes it, for people: "exec_sleep(Seconds, X)",
  // "ood('shutdown_network', X)", "report(Text)".
  std::string prolog_call() const;
};

class Catalogue {
 public:
  // Reads and checks a catalogue file. Errors are InvalidInput with one
  // "path:line:col: message" line per problem, or Io.
  static core::Result<Catalogue> load(const std::string& path);
  // The same from text; source_name labels the errors.
  static core::Result<Catalogue> parse(std::string_view text, const std::string& source_name);
  // config/primitives.toml as compiled in. Parsed on first use; thread-safe.
  static const Catalogue& builtin();
  static std::string_view builtin_text();

  const Primitive* find(std::string_view name) const;
  // The longest time the vehicle takes to answer p (beyond its
  // timeout_plus_arg argument): p's reply_s, else the catalogue's, else
  // its timeout; never past its timeout.
  double reply_bound_s(const Primitive& p) const;
  // In file order.
  const std::vector<Primitive>& all() const { return primitives_; }
  // Where it came from: a path, or "<builtin>/config/primitives.toml".
  const std::string& source() const { return source_; }

 private:
  std::string source_;
  std::optional<double> reply_s_;  // the file's top-level reply_s
  std::vector<Primitive> primitives_;
  std::map<std::string, std::size_t, std::less<>> index_;
};

}  // namespace strata::tactical
