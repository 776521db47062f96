#include "tactical/catalogue.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <set>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "tactical/builtin_catalogue_text.h"  // generated from config/primitives.toml
#include "core/toml_reader.h"

namespace strata::tactical {

namespace {

constexpr std::string_view kBuiltinSource = "<builtin>/config/primitives.toml";
constexpr std::string_view kSetpointFields[] = {"depth_m", "timeout_s"};

constexpr std::string_view kWaypointFields[] = {"x_m", "y_m"};

bool is_setpoint_field(std::string_view name) {
  return std::find(std::begin(kSetpointFields), std::end(kSetpointFields), name) != std::end(kSetpointFields);
}

bool is_waypoint_field(std::string_view name) {
  return std::find(std::begin(kWaypointFields), std::end(kWaypointFields), name) != std::end(kWaypointFields);
}

// Is name a field of the data this primitive reads?
bool is_data_field(DataSource data, std::string_view name) {
  switch (data) {
    case DataSource::None: return false;
    case DataSource::Setpoint: return is_setpoint_field(name);
    case DataSource::Waypoint: return is_waypoint_field(name);
  }
  return false;
}

std::string list_names(const std::vector<std::string>& names) { return fmt::format("{}", fmt::join(names, ", ")); }

// Checks one document against the catalogue's shape, collecting every problem.
class CatalogueReader {
 public:
  explicit CatalogueReader(core::TomlErrors& errors) : errors_(errors) {}
  std::optional<double> reply_s;  // the top level's, once read

  std::vector<Primitive> read(const toml::table& root) {
    std::vector<Primitive> out;
    for (auto&& [key, node] : root) {
      if (key.str() != "primitive" && key.str() != "reply_s") {
        errors_.add(key, fmt::format("unknown key '{}' at the top level: a catalogue holds only "
                                     "reply_s and [[primitive]] tables",
                                     key.str()));
      }
    }
    if (const toml::node* reply = root.get("reply_s")) {
      auto v = core::toml_number(*reply);
      if (!v || !std::isfinite(*v) || *v <= 0) {
        errors_.add(*reply, "reply_s must be a number of seconds above 0");
      } else {
        reply_s = *v;
      }
    }
    const toml::node* list = root.get("primitive");
    if (!list) {
      errors_.add(toml::source_region{{1, 1}, {1, 1}, nullptr}, "no [[primitive]] tables");
      return out;
    }
    const toml::array* array = list->as_array();
    if (array && array->empty()) {
      errors_.add(*list, "the catalogue lists no primitive");
      return out;
    }
    if (!array || !array->is_array_of_tables()) {
      errors_.add(*list, "'primitive' must be an array of tables: write each as [[primitive]]");
      return out;
    }
    std::map<std::string, std::uint32_t, std::less<>> first_line;
    for (const toml::node& node : *array) {
      const toml::table& table = *node.as_table();
      std::optional<Primitive> p = read_primitive(table);
      if (!p) continue;
      auto [it, fresh] = first_line.emplace(p->name, p->line);
      if (!fresh) {
        errors_.add(*table.get("name"), fmt::format("duplicate primitive '{}' (first declared at "
                                                    "line {})",
                                                    p->name, it->second));
        continue;
      }
      out.push_back(std::move(*p));
    }
    return out;
  }

 private:
  const toml::node* string_node(const toml::table& t, std::string_view key, std::string_view owner) {
    const toml::node* n = t.get(key);
    if (n && !n->is_string()) {
      errors_.add(*n, fmt::format("{}: '{}' must be a string, not {}", owner, key, core::toml_type_phrase(*n)));
      return nullptr;
    }
    return n;
  }

  static std::string str(const toml::node& n) { return n.as_string()->get(); }

  std::optional<Primitive> read_primitive(const toml::table& t) {
    static const std::set<std::string, std::less<>> kKeys = {"name", "kind", "args",    "timeout_s", "timeout_plus_arg",
                                                             "data", "doc",  "message", "reply_s"};
    Primitive p;
    p.line = t.source().begin.line;

    const toml::node* name = string_node(t, "name", "[[primitive]]");
    if (!name) {
      if (!t.get("name")) errors_.add(t, "[[primitive]] has no 'name'");
      return std::nullopt;
    }
    p.name = str(*name);
    if (!is_identifier(p.name)) {
      errors_.add(*name, fmt::format("primitive name '{}' is not an identifier (letters, digits, '_')", p.name));
      return std::nullopt;
    }
    const std::string owner = fmt::format("primitive '{}'", p.name);
    bool ok = true;
    for (auto&& [key, node] : t) {
      if (!kKeys.count(key.str())) {
        errors_.add(key, fmt::format("{}: unknown key '{}' (known: args, data, doc, kind, message, "
                                     "name, reply_s, timeout_plus_arg, timeout_s)",
                                     owner, key.str()));
        ok = false;
      }
    }

    const toml::node* kind = string_node(t, "kind", owner);
    if (!kind) {
      if (!t.get("kind")) errors_.add(t, fmt::format("{} has no 'kind' (exec, ask, ood or report)", owner));
      return std::nullopt;
    }
    auto k = core::parse_call_verb(str(*kind));
    if (!k) {
      errors_.add(*kind, fmt::format("{}: unknown kind '{}': expected exec, ask, ood or report", owner, str(*kind)));
      return std::nullopt;
    }
    p.kind = *k;
    const bool report = p.kind == Kind::Report;

    if (const toml::node* doc = string_node(t, "doc", owner)) {
      p.doc = str(*doc);
    } else if (!t.get("doc")) {
      errors_.add(t, fmt::format("{} has no 'doc' (one line for people)", owner));
      ok = false;
    } else {
      ok = false;
    }

    if (const toml::node* data = string_node(t, "data", owner)) {
      if (str(*data) == "setpoint") {
        p.data = DataSource::Setpoint;
      } else if (str(*data) == "waypoint") {
        p.data = DataSource::Waypoint;
      } else {
        errors_.add(*data, fmt::format("{}: unknown data source '{}': the known ones are \"setpoint\" and "
                                       "\"waypoint\"",
                                       owner, str(*data)));
        ok = false;
      }
    }

    bool args_ok = true;
    if (const toml::node* args = t.get("args")) {
      const toml::array* a = args->as_array();
      if (!a || (!a->empty() && !a->is_array_of_tables())) {
        errors_.add(*args, fmt::format("{}: 'args' must be an array of tables", owner));
        args_ok = false;
      } else {
        for (const toml::node& arg : *a) args_ok &= read_argument(*arg.as_table(), p, owner);
      }
    }

    const toml::node* timeout = t.get("timeout_s");
    if (report) {
      if (timeout) {
        errors_.add(*timeout, fmt::format("{}: a report sends nothing to the vehicle, so it has no "
                                          "timeout_s",
                                          owner));
        ok = false;
      }
    } else if (!timeout) {
      errors_.add(t, fmt::format("{} has no 'timeout_s' (the reply timeout, in seconds)", owner));
      ok = false;
    } else {
      auto v = core::toml_number(*timeout);
      if (!v || !std::isfinite(*v) || *v <= 0) {
        errors_.add(*timeout, fmt::format("{}: timeout_s must be a number of seconds above 0", owner));
        ok = false;
      } else {
        p.timeout_s = *v;
      }
    }

    if (const toml::node* reply = t.get("reply_s")) {
      auto v = core::toml_number(*reply);
      if (report) {
        errors_.add(*reply, fmt::format("{}: a report sends nothing to the vehicle, so it has no reply_s", owner));
        ok = false;
      } else if (!v || !std::isfinite(*v) || *v <= 0) {
        errors_.add(*reply, fmt::format("{}: reply_s must be a number of seconds above 0", owner));
        ok = false;
      } else if (p.timeout_s > 0 && *v > p.timeout_s) {
        errors_.add(*reply, fmt::format("{}: reply_s ({} s) must not exceed timeout_s ({} s): a later reply "
                                        "fails the call",
                                        owner, *v, p.timeout_s));
        ok = false;
      } else {
        p.reply_s = *v;
      }
    }

    if (const toml::node* plus = string_node(t, "timeout_plus_arg", owner)) {
      p.timeout_plus_arg = str(*plus);
      const Argument* arg = p.find_arg(p.timeout_plus_arg);
      if (args_ok && (!arg || arg->type != Value::Type::Number || arg->unit != "s")) {
        errors_.add(*plus, fmt::format("{}: timeout_plus_arg '{}' must name a number argument in "
                                       "seconds (unit \"s\")",
                                       owner, p.timeout_plus_arg));
        ok = false;
      }
    } else if (t.get("timeout_plus_arg")) {
      ok = false;
    }

    const toml::node* message = string_node(t, "message", owner);
    if (report) {
      if (message) {
        errors_.add(*message, fmt::format("{}: a report sends nothing to the vehicle, so it has no "
                                          "message",
                                          owner));
        ok = false;
      }
    } else if (!message) {
      if (!t.get("message")) {
        errors_.add(t, fmt::format("{} has no 'message' (the script message it sends)", owner));
      }
      ok = false;
    } else {
      p.message = str(*message);
      // With a broken argument list, placeholder checks would only echo it.
      if (args_ok) ok &= check_message(*message, p, owner);
    }
    if (!ok || !args_ok) return std::nullopt;
    return p;
  }

  bool read_argument(const toml::table& t, Primitive& p, const std::string& owner) {
    static const std::set<std::string, std::less<>> kKeys = {"name", "type", "unit", "min", "max", "default"};
    bool ok = true;
    for (auto&& [key, node] : t) {
      if (!kKeys.count(key.str())) {
        errors_.add(key, fmt::format("{}: unknown argument key '{}' (known: default, max, min, name, "
                                     "type, unit)",
                                     owner, key.str()));
        ok = false;
      }
    }
    Argument a;
    const toml::node* name = string_node(t, "name", owner);
    if (!name) {
      if (!t.get("name")) errors_.add(t, fmt::format("{}: an argument has no 'name'", owner));
      return false;
    }
    a.name = str(*name);
    if (!is_identifier(a.name)) {
      errors_.add(*name, fmt::format("{}: argument name '{}' is not an identifier", owner, a.name));
      return false;
    }
    if (p.find_arg(a.name)) {
      errors_.add(*name, fmt::format("{}: argument '{}' is declared twice", owner, a.name));
      return false;
    }
    if (is_data_field(p.data, a.name)) {
      errors_.add(*name, fmt::format("{}: argument '{}' hides the {} field of that name", owner, a.name,
                                     p.data == DataSource::Setpoint ? "setpoint" : "waypoint"));
      ok = false;
    }
    const std::string what = fmt::format("{}, argument '{}'", owner, a.name);

    const toml::node* type = string_node(t, "type", what);
    if (!type) {
      if (!t.get("type")) errors_.add(t, fmt::format("{} has no 'type' (number or string)", what));
      return false;
    }
    if (str(*type) == "number") {
      a.type = Value::Type::Number;
    } else if (str(*type) == "string") {
      a.type = Value::Type::String;
    } else {
      errors_.add(*type, fmt::format("{}: unknown type '{}': expected number or string", what, str(*type)));
      return false;
    }
    const bool number = a.type == Value::Type::Number;

    if (const toml::node* unit = string_node(t, "unit", what)) {
      a.unit = str(*unit);
    } else if (t.get("unit")) {
      ok = false;
    } else if (number) {
      errors_.add(t, fmt::format("{} has no 'unit' (write unit = \"\" for a pure number)", what));
      ok = false;
    }

    for (auto [key, slot] : {std::pair{"min", &a.min}, std::pair{"max", &a.max}}) {
      const toml::node* n = t.get(key);
      if (!n) continue;
      auto v = core::toml_number(*n);
      if (!number) {
        errors_.add(*n, fmt::format("{}: '{}' applies to numbers only", what, key));
        ok = false;
      } else if (!v || !std::isfinite(*v)) {
        errors_.add(*n, fmt::format("{}: '{}' must be a finite number", what, key));
        ok = false;
      } else {
        *slot = *v;
      }
    }
    if (a.min && a.max && *a.min > *a.max) {
      errors_.add(*t.get("min"), fmt::format("{}: min {} is above max {}", what, *a.min, *a.max));
      ok = false;
    }

    if (const toml::node* d = t.get("default")) {
      std::optional<Value> v;
      if (auto n = core::toml_number(*d); n && number) v = Value::of(*n);
      if (d->is_string() && !number) v = Value::of(str(*d));
      if (!v) {
        errors_.add(*d, fmt::format("{}: the default must be a {}", what, number ? "number" : "string"));
        ok = false;
      } else if (number &&
                 ((a.min && v->number < *a.min) || (a.max && v->number > *a.max) || !std::isfinite(v->number))) {
        errors_.add(*d, fmt::format("{}: the default {} is out of range", what, v->number));
        ok = false;
      } else {
        a.default_value = std::move(v);
      }
    } else if (!p.args.empty() && p.args.back().default_value) {
      errors_.add(t, fmt::format("{}: an argument without a default cannot follow one with a "
                                 "default",
                                 what));
      ok = false;
    }
    p.args.push_back(std::move(a));
    return ok;
  }

  bool check_message(const toml::node& where, const Primitive& p, const std::string& owner) {
    auto parsed = parse_message_template(p.message);
    if (!parsed) {
      errors_.add(where, fmt::format("{}: {}", owner, parsed.error().message));
      return false;
    }
    const auto& fields = parsed.value().fields;
    const std::string_view verb = core::call_verb_name(p.kind);
    if (fields.size() < 2 || !fields[0].is_literal() || fields[0].pieces[0].text != verb) {
      errors_.add(where, fmt::format("{}: the message must start with the verb '{}' and the "
                                     "function's name on the wire, e.g. \"{} {}\"",
                                     owner, verb, verb, p.name));
      return false;
    }
    if (!fields[1].is_literal() || !is_identifier(fields[1].pieces[0].text)) {
      errors_.add(where, fmt::format("{}: the message's second field names the function on the wire "
                                     "and must be a plain identifier",
                                     owner));
      return false;
    }
    bool ok = true;
    std::set<std::string, std::less<>> used;
    std::vector<std::string> known;
    for (const auto& a : p.args) known.push_back(a.name);
    if (p.data == DataSource::Setpoint) {
      for (auto f : kSetpointFields) known.emplace_back(f);
    }
    if (p.data == DataSource::Waypoint) {
      for (auto f : kWaypointFields) known.emplace_back(f);
    }
    for (std::size_t i = 2; i < fields.size(); ++i) {
      for (const auto& piece : fields[i].pieces) {
        if (!piece.is_placeholder) continue;
        used.insert(piece.text);
        if (p.find_arg(piece.text)) continue;
        if (is_data_field(p.data, piece.text)) continue;
        std::string hint =
            known.empty() ? std::string("it has no arguments") : fmt::format("it knows: {}", list_names(known));
        if (is_setpoint_field(piece.text) && p.data != DataSource::Setpoint) {
          hint += "; setpoint fields need data = \"setpoint\"";
        }
        if (is_waypoint_field(piece.text) && p.data != DataSource::Waypoint) {
          hint += "; waypoint fields need data = \"waypoint\"";
        }
        errors_.add(where, fmt::format("{}: placeholder {{{}}} in the message names no argument ({})", owner,
                                       piece.text, hint));
        ok = false;
      }
    }
    for (const auto& a : p.args) {
      if (!used.count(a.name)) {
        errors_.add(where, fmt::format("{}: argument '{}' does not appear in the message; write "
                                       "{{{}}} where it goes",
                                       owner, a.name, a.name));
        ok = false;
      }
    }
    return ok;
  }

  core::TomlErrors& errors_;
};

}  // namespace

core::Result<Catalogue> Catalogue::parse(std::string_view text, const std::string& source_name) {
  auto root = core::parse_toml(text, source_name);
  if (!root) return root.error();
  core::TomlErrors errors(source_name);
  CatalogueReader reader(errors);
  std::vector<Primitive> primitives = reader.read(root.value());
  if (!errors.empty()) return errors.error();
  Catalogue c;
  c.source_ = source_name;
  c.primitives_ = std::move(primitives);
  c.reply_s_ = reader.reply_s;
  for (std::size_t i = 0; i < c.primitives_.size(); ++i) c.index_.emplace(c.primitives_[i].name, i);
  return c;
}

core::Result<Catalogue> Catalogue::load(const std::string& path) {
  auto text = core::read_toml_text(path);
  if (!text) return text.error();
  return parse(text.value(), path);
}

double Catalogue::reply_bound_s(const Primitive& p) const {
  return std::min(p.reply_s.value_or(reply_s_.value_or(p.timeout_s)), p.timeout_s);
}

std::string_view Catalogue::builtin_text() { return kBuiltinCatalogueText; }

const Catalogue& Catalogue::builtin() {
  static const Catalogue catalogue = [] {
    auto c = parse(kBuiltinCatalogueText, std::string(kBuiltinSource));
    if (!c) {
      // A broken built-in catalogue is a build defect (catalogue_test guards it).
      std::fprintf(stderr, "strata: the built-in primitive catalogue is invalid:\n%s\n", c.error().message.c_str());
      std::abort();
    }
    return std::move(c).value();
  }();
  return catalogue;
}

const Primitive* Catalogue::find(std::string_view name) const {
  auto it = index_.find(name);
  return it == index_.end() ? nullptr : &primitives_[it->second];
}

}  // namespace strata::tactical
