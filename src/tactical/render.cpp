#include "tactical/render.h"

#include <cmath>
#include <optional>

#include <fmt/format.h>

namespace strata::tactical {

namespace {

core::Error invalid(std::string message) { return core::make_error(core::ErrorCode::InvalidInput, std::move(message)); }

std::string describe(const Value& v) {
  return v.type == Value::Type::Number ? fmt::format("number {}", to_string(v)) : fmt::format("string \"{}\"", v.text);
}

std::string with_unit(double n, const std::string& unit) {
  return unit.empty() ? to_string(Value::of(n)) : fmt::format("{} {}", to_string(Value::of(n)), unit);
}

std::string arity_text(const Primitive& p) {
  std::string names;
  for (const auto& a : p.args) {
    if (!names.empty()) names += ", ";
    names += a.name;
  }
  std::size_t lo = p.min_args(), hi = p.max_args();
  if (hi == 0) return "no arguments";
  std::string count =
      lo == hi ? fmt::format("{} argument{}", hi, hi == 1 ? "" : "s") : fmt::format("{} to {} arguments", lo, hi);
  return fmt::format("{} ({})", count, names);
}

bool is_token(std::string_view s) {
  if (s.empty()) return false;
  for (char c : s) {
    auto u = static_cast<unsigned char>(c);
    if (u <= 0x20 || u == 0x7f) return false;
  }
  return true;
}

}  // namespace

std::string RenderedCall::text() const {
  std::string out;
  if (to_vehicle()) {
    out = core::call_verb_name(verb);
    out += ' ';
    out += name;
  }
  for (const auto& a : args) {
    if (!out.empty()) out += ' ';
    out += to_string(a);
  }
  return out;
}

core::Result<std::vector<Value>> check_args(const Primitive& p, std::span<const Value> args) {
  if (args.size() < p.min_args() || args.size() > p.max_args()) {
    return invalid(fmt::format("'{}' takes {}, but {} given", p.name, arity_text(p), args.size()));
  }
  std::vector<Value> out;
  out.reserve(p.args.size());
  for (std::size_t i = 0; i < p.args.size(); ++i) {
    const Argument& a = p.args[i];
    if (i >= args.size()) {
      out.push_back(*a.default_value);  // min_args() counted the ones without
      continue;
    }
    const Value& v = args[i];
    if (v.type != a.type) {
      return invalid(fmt::format("'{}' argument '{}' must be a {}, not the {}", p.name, a.name,
                                 a.type == Value::Type::Number ? "number" : "string", describe(v)));
    }
    if (v.type == Value::Type::Number) {
      if (!std::isfinite(v.number)) {
        return invalid(fmt::format("'{}' argument '{}' must be a finite number", p.name, a.name));
      }
      if (a.min && v.number < *a.min) {
        return invalid(fmt::format("'{}' argument '{}' is {}, below the minimum {}", p.name, a.name,
                                   with_unit(v.number, a.unit), with_unit(*a.min, a.unit)));
      }
      if (a.max && v.number > *a.max) {
        return invalid(fmt::format("'{}' argument '{}' is {}, above the maximum {}", p.name, a.name,
                                   with_unit(v.number, a.unit), with_unit(*a.max, a.unit)));
      }
    }
    out.push_back(v);
  }
  return out;
}

core::Result<RenderedCall> render(const Primitive& p, std::span<const Value> args, const DataCursor* cursor) {
  auto checked = check_args(p, args);
  if (!checked) return checked.error();
  const std::vector<Value>& values = checked.value();

  RenderedCall call;
  call.timeout_s = p.timeout_s;
  if (!p.timeout_plus_arg.empty()) {
    for (std::size_t i = 0; i < p.args.size(); ++i) {
      if (p.args[i].name == p.timeout_plus_arg) call.timeout_s += values[i].number;
    }
  }
  call.verb = p.kind;
  if (p.kind == Kind::Report) {
    call.name = p.name;
    call.args = values;
    return call;
  }

  const Setpoint* setpoint = nullptr;
  if (p.data == DataSource::Setpoint) {
    setpoint = cursor ? cursor->current() : nullptr;
    if (!setpoint) {
      return invalid(fmt::format("'{}' reads the mission data, but no setpoint has been read", p.name));
    }
  }
  const Waypoint* waypoint = nullptr;
  if (p.data == DataSource::Waypoint) {
    waypoint = cursor ? cursor->current_waypoint() : nullptr;
    if (!waypoint) {
      return invalid(fmt::format("'{}' reads the mission data, but no waypoint has been read", p.name));
    }
  }

  auto parsed = parse_message_template(p.message);
  if (!parsed) return invalid(fmt::format("'{}': {}", p.name, parsed.error().message));
  const auto& fields = parsed.value().fields;
  if (fields.size() < 2 || !fields[0].is_literal() || !fields[1].is_literal()) {
    return invalid(fmt::format("'{}': the message \"{}\" does not start with a verb and a name", p.name, p.message));
  }
  // The catalogue checked that the first field is the verb (p.kind).
  call.name = fields[1].pieces[0].text;
  for (std::size_t f = 2; f < fields.size(); ++f) {
    std::string field;
    std::optional<Value> whole;  // the field is exactly one placeholder
    for (const auto& piece : fields[f].pieces) {
      if (!piece.is_placeholder) {
        field += piece.text;
        continue;
      }
      std::optional<Value> v;
      for (std::size_t i = 0; i < p.args.size(); ++i) {
        if (p.args[i].name == piece.text) v = values[i];
      }
      if (!v && setpoint && piece.text == "depth_m") v = Value::of(setpoint->depth_m);
      if (!v && setpoint && piece.text == "timeout_s") v = Value::of(setpoint->timeout_s);
      if (!v && waypoint && piece.text == "x_m") v = Value::of(waypoint->x_m);
      if (!v && waypoint && piece.text == "y_m") v = Value::of(waypoint->y_m);
      if (!v) {
        return invalid(fmt::format("'{}': placeholder {{{}}} in the message names no argument", p.name, piece.text));
      }
      std::string s = to_string(*v);
      if (v->type == Value::Type::String && !is_token(s)) {
        return invalid(
            fmt::format("'{}' argument '{}' must be one word (no spaces or control "
                        "characters) to go into the message, not \"{}\"",
                        p.name, piece.text, s));
      }
      field += s;
      if (fields[f].pieces.size() == 1) whole = std::move(v);
    }
    call.args.push_back(whole ? std::move(*whole) : Value::of(std::move(field)));
  }
  return call;
}

core::Result<RenderedCall> advance_and_render(const Primitive& p, std::span<const Value> args, DataCursor& cursor) {
  auto checked = check_args(p, args);
  if (!checked) return checked.error();
  if (p.data == DataSource::Setpoint) {
    auto next = cursor.next();
    if (!next) return next.error();
  }
  if (p.data == DataSource::Waypoint) {
    auto next = cursor.next_waypoint();
    if (!next) return next.error();
  }
  return render(p, args, &cursor);
}

}  // namespace strata::tactical
