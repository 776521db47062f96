#include "run/inputs.h"

#include <cstdlib>
#include <filesystem>

#include <asio.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "run/scenario_folder.h"

namespace strata::run {

core::Result<tactical::Catalogue> load_catalogue_option(const std::string& path) {
  if (path.empty()) return tactical::Catalogue::builtin();
  return tactical::Catalogue::load(path);
}

core::Result<std::pair<std::string, std::uint16_t>> parse_listen(const std::string& text) {
  std::string host = "127.0.0.1";
  std::string port = text;
  if (auto colon = text.rfind(':'); colon != std::string::npos) {
    host = text.substr(0, colon);
    port = text.substr(colon + 1);
  }
  char* end = nullptr;
  long value = std::strtol(port.c_str(), &end, 10);
  if (port.empty() || *end != '\0' || value < 0 || value > 65535) {
    return core::make_error(core::ErrorCode::InvalidInput,
                            fmt::format("'{}' is not a port (0-65535) or ADDRESS:PORT", text));
  }
  if (host == "localhost") host = "127.0.0.1";
  asio::error_code ec;
  asio::ip::make_address_v4(host, ec);
  if (ec) {
    return core::make_error(core::ErrorCode::InvalidInput,
                            fmt::format("'{}' is not an IPv4 address (e.g. 127.0.0.1)", host));
  }
  return std::make_pair(host, static_cast<std::uint16_t>(value));
}

core::Result<vehicle::Scenario> load_scenario_option(const std::string& scenario, const std::string& mission) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (scenario.empty()) {
    // The mission's own nominal scenario (where its target is, say), else
    // the built-in one: no faults, seed 1.
    if (!mission.empty()) {
      fs::path nominal = scenario_path(mission, "nominal");
      if (fs::is_regular_file(nominal, ec)) return vehicle::load_scenario(nominal.string());
    }
    return vehicle::Scenario::nominal();
  }
  if (fs::is_regular_file(scenario, ec)) return vehicle::load_scenario(scenario);
  if (!mission.empty()) {
    fs::path beside = scenario_path(mission, scenario);
    if (fs::is_regular_file(beside, ec)) return vehicle::load_scenario(beside.string());
    // The names there, so that a typo is one look away.
    const std::vector<std::string> names = scenario_names_in(beside.parent_path());
    return core::make_error(core::ErrorCode::Io,
                            fmt::format("no scenario '{}': neither a file nor {}; {}", scenario, beside.string(),
                                        names.empty() ? "that folder has no scenarios"
                                                      : fmt::format("its scenarios: {}", fmt::join(names, ", "))));
  }
  return core::make_error(core::ErrorCode::Io, fmt::format("no scenario file '{}' (give a path, or --mission to look "
                                                           "in the mission's scenarios/ folder)",
                                                           scenario));
}

core::Result<vehicle::Scenario> load_scenario_through(
    const std::function<core::Result<std::string>(const std::string&)>& read, const std::string& scenario,
    const std::string& mission) {
  if (scenario.empty()) {
    if (mission.empty()) return vehicle::Scenario::nominal();
    const std::string nominal = scenario_path(mission, "nominal").string();
    auto text = read(nominal);
    if (text) return vehicle::parse_scenario(text.value(), nominal);
    if (text.error().code == core::ErrorCode::Io) return vehicle::Scenario::nominal();
    return core::make_error(text.error().code, fmt::format("the nominal scenario: {}", text.error().message));
  }
  auto text = read(scenario);
  if (!text) return core::make_error(text.error().code, fmt::format("scenario: {}", text.error().message));
  return vehicle::parse_scenario(text.value(), scenario);
}

}  // namespace strata::run
