#include "cli/user_config.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <ctime>
#include <map>

#include <fmt/format.h>

#include "core/text.h"
#include "core/toml_reader.h"
#include "run/inputs.h"

namespace strata::cli {
namespace {

namespace fs = std::filesystem;

// The keys each table may hold, in the order `config show` prints them.
const std::map<std::string, std::vector<std::string>>& known_keys() {
  static const std::map<std::string, std::vector<std::string>> keys = {
      {"run", {"vehicle", "telemetry_hz", "log", "log_dir"}},
      {"vehicle", {"listen"}},
      {"studio", {"listen"}},
  };
  return keys;
}

// What follows "unknown key 'x'": the known names, and the closest of them
// when one is a typo away.
std::string known_tail(std::string_view name, const std::vector<std::string>& known, std::string_view what,
                       const std::string& listed) {
  const auto s = core::suggest(name, known);
  if (!s) return fmt::format("; {}: {}", what, listed);
  return fmt::format(": did you mean '{}'? ({}: {})", *s, what, listed);
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

std::string nonempty(const char* value) { return value && *value ? value : ""; }

// "~/x" with HOME; anything else as it is.
std::string expand_home(const std::string& path, const Getenv& getenv) {
  const std::string home = nonempty(getenv("HOME"));
  if (path == "~") return home.empty() ? path : home;
  if (path.starts_with("~/") && !home.empty()) return home + path.substr(1);
  return path;
}

class Reader {
 public:
  Reader(const std::string& path, UserConfig& config, const Getenv& getenv)
      : path_(path), errors_(path), config_(config), getenv_(getenv) {}

  void read(const toml::table& root) {
    for (const auto& [table_key, node] : root) {
      const std::string table(table_key.str());
      auto known = known_keys().find(table);
      if (known == known_keys().end()) {
        std::vector<std::string> tables;
        for (const auto& [name, keys] : known_keys()) tables.push_back("[" + name + "]");
        std::vector<std::string> names;
        for (const auto& [name, keys] : known_keys()) names.push_back(name);
        errors_.add(table_key,
                    fmt::format("unknown table [{}]{}", table, known_tail(table, names, "the tables", joined(tables))));
        continue;
      }
      const toml::table* entries = node.as_table();
      if (!entries) {
        errors_.add(node, fmt::format("'{}' must be a table ([{}])", table, table));
        continue;
      }
      for (const auto& [key, value] : *entries) read_key(table, std::string(key.str()), key, value, known->second);
    }
  }

  core::Result<void> result() const {
    if (errors_.empty()) return {};
    return errors_.error();
  }

 private:
  std::string origin(const toml::node& node) const { return fmt::format("{}:{}", path_, node.source().begin.line); }

  std::optional<std::string> string_of(const toml::node& node, const std::string& name) {
    if (const auto* s = node.as_string()) return s->get();
    errors_.add(node, fmt::format("'{}' must be a string, not {}", name, core::toml_type_phrase(node)));
    return std::nullopt;
  }

  // An address: ADDRESS:PORT or PORT (IPv4), as --listen and --vehicle take it.
  void address(Setting<std::string>& into, const toml::node& node, const std::string& name, bool embedded_allowed) {
    auto text = string_of(node, name);
    if (!text) return;
    if (!(embedded_allowed && *text == "embedded")) {
      auto parsed = run::parse_listen(*text);
      if (!parsed) {
        errors_.add(node, fmt::format("'{}': {}", name, parsed.error().message));
        return;
      }
      if (embedded_allowed && parsed.value().second == 0) {  // an address to connect to
        errors_.add(node,
                    fmt::format("'{}': port 0 is not a vehicle's port (\"embedded\" for the simulated one)", name));
        return;
      }
    }
    into = {*text, origin(node)};
  }

  void read_key(const std::string& table, const std::string& key, const toml::key& where, const toml::node& value,
                const std::vector<std::string>& keys) {
    const std::string name = table + "." + key;
    if (name == "run.vehicle") {
      address(config_.run_vehicle, value, name, /*embedded_allowed=*/true);
    } else if (name == "run.telemetry_hz") {
      auto hz = core::toml_number(value);
      if (!hz || !std::isfinite(*hz) || *hz < 0.0 || *hz > 100.0) {
        errors_.add(value, fmt::format("'{}' must be a number from 0 to 100 (per simulated second)", name));
        return;
      }
      config_.run_telemetry_hz = {*hz, origin(value)};
    } else if (name == "run.log") {
      if (const auto* b = value.as_boolean()) {
        config_.run_log = {b->get(), origin(value)};
      } else {
        errors_.add(value, fmt::format("'{}' must be true or false, not {}", name, core::toml_type_phrase(value)));
      }
    } else if (name == "run.log_dir") {
      auto dir = string_of(value, name);
      if (!dir) return;
      if (dir->empty()) {
        errors_.add(value, fmt::format("'{}' must name a folder (to log no run: log = false)", name));
        return;
      }
      const std::string expanded = expand_home(*dir, getenv_);
      if (!fs::path(expanded).is_absolute()) {
        errors_.add(value, fmt::format("'{}' must be an absolute path or start with ~/ (a relative one would "
                                       "change with the folder strata runs in)",
                                       name));
        return;
      }
      config_.run_log_dir = {expanded, origin(value)};
    } else if (name == "vehicle.listen") {
      address(config_.vehicle_listen, value, name, false);
    } else if (name == "studio.listen") {
      address(config_.studio_listen, value, name, false);
    } else {
      errors_.add(where, fmt::format("unknown key '{}' in [{}]{}", key, table,
                                     known_tail(key, keys, "its keys", joined(keys))));
    }
  }

  std::string path_;
  core::TomlErrors errors_;
  UserConfig& config_;
  const Getenv& getenv_;
};

std::string quoted(const std::string& s) { return "\"" + s + "\""; }

}  // namespace

core::Result<UserConfig> load_user_config(const Getenv& getenv) {
  UserConfig config;
  const std::string home = nonempty(getenv("HOME"));
  const std::string state = nonempty(getenv("XDG_STATE_HOME"));
  if (!state.empty()) {
    config.run_log_dir = {(fs::path(state) / "strata" / "logs").string(), "built in ($XDG_STATE_HOME)"};
  } else if (!home.empty()) {
    config.run_log_dir = {(fs::path(home) / ".local/state/strata/logs").string(), "built in (~/.local/state)"};
  }

  const std::string named = nonempty(getenv("STRATA_CONFIG"));
  const std::string xdg = nonempty(getenv("XDG_CONFIG_HOME"));
  if (!named.empty()) {
    config.path = named;
  } else if (!xdg.empty()) {
    config.path = (fs::path(xdg) / "strata" / "config.toml").string();
  } else if (!home.empty()) {
    config.path = (fs::path(home) / ".config" / "strata" / "config.toml").string();
  }
  std::error_code ec;
  const bool exists = !config.path.empty() && fs::exists(fs::symlink_status(config.path, ec));
  if (!named.empty() && !exists) {
    return core::make_error(core::ErrorCode::Io,
                            fmt::format("{}: no such config file (named by STRATA_CONFIG)", config.path));
  }
  if (exists) {
    auto table = core::parse_toml_file(config.path);
    if (!table) return table.error();
    Reader reader(config.path, config, getenv);
    reader.read(table.value());
    if (auto r = reader.result(); !r) return r.error();
    config.found = true;
  }
  if (const std::string dir = nonempty(getenv("STRATA_LOG_DIR")); !dir.empty()) {
    config.run_log_dir = {expand_home(dir, getenv), "STRATA_LOG_DIR"};
  }
  return config;
}

std::optional<int> config_failure(const LoadedConfig& loaded, const std::string& command) {
  if (!loaded.error) return std::nullopt;
  fmt::print(stderr, "strata {}: {}\n(the config file; `strata config path` names it)\n", command,
             loaded.error->message);
  return loaded.error->code == core::ErrorCode::Io ? 74 : 65;
}

std::string config_text(const UserConfig& c) {
  std::string out = c.path.empty() ? "# no config file: neither XDG_CONFIG_HOME nor HOME is set\n"
                    : c.found      ? fmt::format("# from {}\n", c.path)
                                   : fmt::format("# {} does not exist: built-in values\n", c.path);
  auto line = [&out](const std::string& name, const std::string& value, const std::string& origin) {
    out += fmt::format("{:<20} = {:<28} # {}\n", name, value, origin);
  };
  out += "[run]\n";
  line("vehicle", quoted(c.run_vehicle.value), c.run_vehicle.origin);
  line("telemetry_hz", fmt::format("{:g}", c.run_telemetry_hz.value), c.run_telemetry_hz.origin);
  line("log", c.run_log.value ? "true" : "false", c.run_log.origin);
  line("log_dir", quoted(c.run_log_dir.value), c.run_log_dir.value.empty() ? "no HOME: none" : c.run_log_dir.origin);
  out += "[vehicle]\n";
  line("listen", quoted(c.vehicle_listen.value), c.vehicle_listen.origin);
  out += "[studio]\n";
  line("listen", quoted(c.studio_listen.value), c.studio_listen.origin);
  return out;
}

}  // namespace strata::cli
