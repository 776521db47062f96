#pragma once
// The operator's defaults: $XDG_CONFIG_HOME/strata/config.toml (else
// ~/.config/strata/config.toml, or the file $STRATA_CONFIG names), read
// before any command runs. The command line beats the environment
// (STRATA_LOG_DIR), which beats the file, which beats the built-in value.
// `strata config show` prints every setting with where it came from.
//
//   [run]
//   vehicle = "127.0.0.1:7020"   # default --vehicle; "embedded": the simulated one
//   telemetry_hz = 5             # default --telemetry-hz (built in: 2)
//   log = true                   # log every run to a dated file (--no-log: not this one)
//   log_dir = "~/auv/logs"       # where (default $XDG_STATE_HOME/strata/logs)
//   [vehicle]
//   listen = "127.0.0.1:7020"    # `strata vehicle --listen`
//   [studio]
//   listen = "127.0.0.1:0"       # `strata studio --listen`
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"
#include "run/options.h"

namespace strata::cli {

template <typename T>
struct Setting {
  T value{};
  std::string origin = "built in";  // "built in", "PATH:LINE", "STRATA_LOG_DIR", ...
};

struct UserConfig {
  std::string path;    // the file looked for ("" when there is no home to look in)
  bool found = false;  // it exists and was read
  Setting<std::string> run_vehicle{"embedded"};
  Setting<double> run_telemetry_hz{run::RunOptions{}.telemetry_hz};
  Setting<bool> run_log{true};
  Setting<std::string> run_log_dir;  // "" when neither set nor derivable (no HOME)
  Setting<std::string> vehicle_listen{"127.0.0.1:7020"};
  Setting<std::string> studio_listen{"127.0.0.1:0"};
};

// What main loaded: the settings, or why they could not be (then every
// command that uses them says so and exits 65, or 74 for a file it cannot
// read; the others run on).
struct LoadedConfig {
  UserConfig config;
  std::optional<core::Error> error;
};

// With loaded.error: prints "strata COMMAND: <error>" and returns the exit
// code; nullopt when the settings are good.
std::optional<int> config_failure(const LoadedConfig& loaded, const std::string& command);

// The environment, as the loader sees it (tests pass their own).
using Getenv = std::function<const char*(const char*)>;

// The settings, from the file and the environment. A missing file at the
// default place is no error (the built-in values); a file named by
// $STRATA_CONFIG must exist. Every problem is located ("path:line:col:
// message", InvalidInput; Io for a file that cannot be read), unknown keys
// listed with the valid ones.
core::Result<UserConfig> load_user_config(const Getenv& getenv = std::getenv);

// Every setting, one a line: "run.log_dir = "/root/..."   # from STRATA_LOG_DIR".
std::string config_text(const UserConfig& config);

}  // namespace strata::cli
