#include "tactical/catalogue_print.h"

#include <algorithm>
#include <array>

#include <fmt/format.h>

namespace strata::tactical {

namespace {

std::string num(double n) { return to_string(Value::of(n)); }

nlohmann::ordered_json value_json(const Value& v) {
  if (v.type == Value::Type::String) return v.text;
  return v.number;
}

std::string timeout_text(const Primitive& p) {
  if (p.kind == Kind::Report) return "-";
  std::string out = fmt::format("{} s", num(p.timeout_s));
  if (!p.timeout_plus_arg.empty()) out += " + " + p.timeout_plus_arg;
  return out;
}

}  // namespace

std::string describe_argument(const Argument& a) {
  std::vector<std::string> parts;
  if (a.type == Value::Type::String) {
    parts.emplace_back("string");
  } else if (!a.unit.empty()) {
    parts.push_back(a.unit);
  } else {
    parts.emplace_back("number");
  }
  if (a.min || a.max) {
    parts.push_back(fmt::format("{}..{}", a.min ? num(*a.min) : "", a.max ? num(*a.max) : ""));
  }
  if (a.default_value) {
    parts.push_back(a.default_value->type == Value::Type::String
                        ? fmt::format("default \"{}\"", a.default_value->text)
                        : fmt::format("default {}", num(a.default_value->number)));
  }
  std::string inner;
  for (const auto& part : parts) {
    if (!inner.empty()) inner += ", ";
    inner += part;
  }
  return fmt::format("{} ({})", a.name, inner);
}

std::string format_catalogue(const Catalogue& catalogue) {
  using Row = std::array<std::string, 7>;
  std::vector<Row> rows;
  rows.push_back({"NAME", "KIND", "ARGUMENTS", "TIMEOUT", "PROLOG", "MESSAGE", "DOC"});
  for (const auto& p : catalogue.all()) {
    std::string args;
    for (const auto& a : p.args) {
      if (!args.empty()) args += ", ";
      args += describe_argument(a);
    }
    std::string message = p.kind == Kind::Report ? "(console and log only)" : p.message;
    rows.push_back({p.name, std::string(core::call_verb_name(p.kind)), args.empty() ? "-" : args, timeout_text(p),
                    p.prolog_call(), message, p.doc});
  }
  std::array<std::size_t, 7> width{};
  for (const auto& row : rows) {
    for (std::size_t c = 0; c < row.size(); ++c) width[c] = std::max(width[c], row[c].size());
  }
  std::string out;
  for (const auto& row : rows) {
    std::string line;
    for (std::size_t c = 0; c < row.size(); ++c) {
      if (c + 1 == row.size()) {
        line += row[c];
      } else {
        line += fmt::format("{:<{}}  ", row[c], width[c]);
      }
    }
    while (!line.empty() && line.back() == ' ') line.pop_back();
    out += line;
    out += '\n';
  }
  out += fmt::format("\n{} primitives from {}\n", catalogue.all().size(), catalogue.source());
  return out;
}

nlohmann::ordered_json catalogue_json(const Catalogue& catalogue) {
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const auto& p : catalogue.all()) {
    nlohmann::ordered_json j;
    j["name"] = p.name;
    j["kind"] = core::call_verb_name(p.kind);
    nlohmann::ordered_json args = nlohmann::ordered_json::array();
    for (const auto& a : p.args) {
      nlohmann::ordered_json arg;
      arg["name"] = a.name;
      arg["type"] = a.type == Value::Type::Number ? "number" : "string";
      arg["unit"] = a.unit;
      if (a.min) arg["min"] = *a.min;
      if (a.max) arg["max"] = *a.max;
      if (a.default_value) arg["default"] = value_json(*a.default_value);
      args.push_back(std::move(arg));
    }
    j["args"] = std::move(args);
    if (p.kind != Kind::Report) j["timeout_s"] = p.timeout_s;
    if (!p.timeout_plus_arg.empty()) j["timeout_plus_arg"] = p.timeout_plus_arg;
    if (p.data == DataSource::Setpoint) j["data"] = "setpoint";
    if (p.data == DataSource::Waypoint) j["data"] = "waypoint";
    j["prolog"] = p.prolog_predicate();
    j["doc"] = p.doc;
    if (p.kind != Kind::Report) j["message"] = p.message;
    list.push_back(std::move(j));
  }
  nlohmann::ordered_json out;
  out["source"] = catalogue.source();
  out["primitives"] = std::move(list);
  return out;
}

}  // namespace strata::tactical
