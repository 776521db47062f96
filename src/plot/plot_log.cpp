#include "plot/plot_log.h"

#include <algorithm>
#include <sstream>
#include <limits>
#include <map>
#include <optional>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/file.h"

namespace strata::plot {
namespace {

using nlohmann::json;

// Where a field's problem is reported: "log.jsonl:12: ".
struct Place {
  std::string_view name;
  std::size_t line;
};

core::Error invalid(const Place& at, std::string_view what) {
  return core::make_error(core::ErrorCode::InvalidInput, fmt::format("{}:{}: {}", at.name, at.line, what));
}

// A number field: nullopt when absent or null, an error when of another type.
core::Result<std::optional<double>> number(const json& e, const char* key, const Place& at) {
  auto it = e.find(key);
  if (it == e.end() || it->is_null()) return std::optional<double>{};
  if (!it->is_number()) {
    return invalid(at, fmt::format("{}: '{}' is not a number", e.value("event", "event"), key));
  }
  return std::optional<double>{it->get<double>()};
}

// A text field: "" when absent or null.
core::Result<std::string> text(const json& e, const char* key, const Place& at) {
  auto it = e.find(key);
  if (it == e.end() || it->is_null()) return std::string{};
  if (!it->is_string()) return invalid(at, fmt::format("{}: '{}' is not a string", e.value("event", "event"), key));
  return it->get<std::string>();
}

core::Result<std::uint64_t> count(const json& e, const char* key, const Place& at) {
  auto it = e.find(key);
  if (it == e.end() || !it->is_number_unsigned()) {
    return invalid(at, fmt::format("{}: '{}' is missing or not a count", e.value("event", "event"), key));
  }
  return it->get<std::uint64_t>();
}

// Reads one event into `plot`; `open` maps a running phase's instance to its
// index in plot.phases.
core::Result<void> read_event(const json& e, const Place& at, MissionPlot& plot,
                              std::map<std::uint64_t, std::size_t>& open) {
  auto event_it = e.find("event");
  if (event_it == e.end() || !event_it->is_string()) return invalid(at, "no \"event\" name");
  const std::string& event = event_it->get_ref<const std::string&>();

  auto time = number(e, "sim_time", at);
  if (!time) return time.error();
  if (time.value()) {
    plot.first_s = std::min(plot.first_s, *time.value());
    plot.last_s = std::max(plot.last_s, *time.value());
  }
  auto need_time = [&]() -> core::Result<double> {
    if (!time.value()) return invalid(at, fmt::format("{}: no 'sim_time'", event));
    return *time.value();
  };

  if (event == "run") {
    auto mission = text(e, "mission", at);
    if (!mission) return mission.error();
    auto scenario = text(e, "scenario", at);
    if (!scenario) return scenario.error();
    plot.mission = mission.value();
    plot.scenario = scenario.value();
  } else if (event == "telemetry") {
    auto t = need_time();
    if (!t) return t.error();
    const std::pair<const char*, Series*> fields[] = {{"depth_m", &plot.depth_m},
                                                      {"filtered_depth_m", &plot.filtered_depth_m},
                                                      {"setpoint_m", &plot.setpoint_m},
                                                      {"heading_deg", &plot.heading_deg}};
    for (const auto& [key, series] : fields) {
      auto v = number(e, key, at);
      if (!v) return v.error();
      if (!v.value()) continue;
      series->time_s.push_back(t.value());
      series->value.push_back(*v.value());
    }
  } else if (event == "phase_start") {
    auto t = need_time();
    if (!t) return t.error();
    auto instance = count(e, "instance", at);
    if (!instance) return instance.error();
    auto depth = count(e, "depth", at);
    if (!depth) return depth.error();
    auto net = text(e, "net", at);
    if (!net) return net.error();
    if (depth.value() == 0) return {};  // the global net: the whole mission
    open[instance.value()] = plot.phases.size();
    PhaseBand band;
    band.instance = instance.value();
    band.net = net.value();
    band.depth = static_cast<int>(std::min<std::uint64_t>(depth.value(), 1000));
    band.start_s = t.value();
    plot.phases.push_back(band);
  } else if (event == "phase_end") {
    auto t = need_time();
    if (!t) return t.error();
    auto instance = count(e, "instance", at);
    if (!instance) return instance.error();
    auto result = text(e, "result", at);
    if (!result) return result.error();
    auto exit = text(e, "exit", at);
    if (!exit) return exit.error();
    auto it = open.find(instance.value());
    if (it == open.end()) return {};  // the global net, or a start the log lost
    PhaseBand& band = plot.phases[it->second];
    open.erase(it);
    band.end_s = t.value();
    band.result = result.value();
    band.exit = exit.value();
    band.ended = true;
    if (band.result != "completed") {
      std::string label = fmt::format("{} {}", band.net, band.result.empty() ? "ended" : band.result);
      if (!band.exit.empty()) label += fmt::format(" (exit {})", band.exit);
      plot.aborts.push_back({band.end_s, std::move(label), false});
    }
  } else if (event == "mission_end") {
    auto t = need_time();
    if (!t) return t.error();
    for (auto [key, field] :
         {std::pair{"outcome", &plot.outcome}, std::pair{"exit", &plot.exit}, std::pair{"reason", &plot.reason}}) {
      auto v = text(e, key, at);
      if (!v) return v.error();
      *field = v.value();
    }
    plot.ended = true;
    if (plot.outcome != "completed") {
      std::string label = fmt::format("mission {}", plot.outcome.empty() ? "ended" : plot.outcome);
      if (!plot.exit.empty()) label += fmt::format(" (exit {})", plot.exit);
      if (!plot.reason.empty()) label += fmt::format(": {}", plot.reason);
      // The mark goes where the mission ended, before the run's safe end
      // (mission_sim_time; older logs have only sim_time).
      const double at_s = e.contains("mission_sim_time") && e["mission_sim_time"].is_number()
                              ? e["mission_sim_time"].get<double>()
                              : t.value();
      plot.aborts.push_back({at_s, std::move(label), true});
    }
  }
  return {};
}

}  // namespace

std::string MissionPlot::title() const {
  std::string t = mission.empty() ? std::string("mission log") : mission;
  if (!scenario.empty()) t += fmt::format(", scenario {}", scenario);
  if (!ended) return t + ": the log ends before the mission did";
  t += fmt::format(": {}", outcome.empty() ? "ended" : outcome);
  if (!exit.empty()) t += fmt::format(" (exit {})", exit);
  return t;
}

core::Result<MissionPlot> read_log(std::istream& in, std::string_view name) {
  MissionPlot plot;
  plot.first_s = std::numeric_limits<double>::infinity();
  plot.last_s = -std::numeric_limits<double>::infinity();
  std::map<std::uint64_t, std::size_t> open;
  std::string line;
  for (std::size_t n = 1; std::getline(in, line); ++n) {
    const Place at{name, n};
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    json e;
    try {
      e = json::parse(line);
    } catch (const json::parse_error& error) {
      return invalid(at, fmt::format("not JSON (column {})", error.byte));
    }
    if (!e.is_object()) return invalid(at, "not a JSON object");
    auto read = read_event(e, at, plot, open);
    if (!read) return read.error();
  }
  if (in.bad()) return core::make_error(core::ErrorCode::Io, fmt::format("cannot read '{}'", name));
  if (plot.depth_m.empty()) {
    return core::make_error(core::ErrorCode::InvalidInput,
                            fmt::format("{}: no telemetry with depth_m: nothing to plot", name));
  }
  // A phase still running when the log stops is drawn to the log's end.
  for (const auto& [instance, index] : open) plot.phases[index].end_s = plot.last_s;
  return plot;
}

core::Result<MissionPlot> read_log_file(const std::string& path) {
  auto text = core::read_regular_file(path, kMaxLogBytes, [](const std::string& p, const char* reason) {
    return fmt::format("cannot open '{}': {}", p, reason);
  });
  if (!text) return text.error();
  std::istringstream in(std::move(text).value());
  return read_log(in, path);
}

}  // namespace strata::plot
