#include "plot/plot_log.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
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

void note(MissionPlot& plot, const Place& at, std::string_view what) {
  if (plot.notes.size() < kMaxNotes) {
    plot.notes.push_back(fmt::format("{}:{}: {}", at.name, at.line, what));
  } else {
    ++plot.skipped_notes;
  }
}

// A value that can be drawn: finite and within kMaxCoordinate_m.
bool drawable(double v) { return std::isfinite(v) && std::abs(v) <= kMaxCoordinate_m; }

// The guidance call or fix of a request, kept until its reply says whether
// the vehicle accepted it.
struct Pending {
  double time_s = 0.0;
  std::string name;  // goto_xy, track, gps_fix
  std::vector<double> args;
};

struct ReadState {
  std::map<std::uint64_t, std::size_t> open;  // a running phase's instance -> index in plot.phases
  std::map<std::uint64_t, Pending> pending;   // request id -> its call
};

// The horizontal pair (x_key, y_key) of a telemetry line into `path`.
core::Result<void> read_pair(const json& e, const char* x_key, const char* y_key, double t, const Place& at,
                             MissionPlot& plot, Path& path) {
  auto x = number(e, x_key, at);
  if (!x) return x.error();
  auto y = number(e, y_key, at);
  if (!y) return y.error();
  if (!x.value() && !y.value()) return {};
  if (!x.value() || !y.value()) {
    note(plot, at,
         fmt::format("telemetry: {} without {}: skipped", x.value() ? x_key : y_key, x.value() ? y_key : x_key));
    return {};
  }
  for (auto [key, v] : {std::pair{x_key, *x.value()}, std::pair{y_key, *y.value()}}) {
    if (!drawable(v)) {
      note(plot, at, fmt::format("telemetry: {} {} is beyond {} km: skipped", key, v, kMaxCoordinate_m / 1000));
      return {};
    }
  }
  path.time_s.push_back(t);
  path.at.push_back({*x.value(), *y.value()});
  return {};
}

// "exec goto_xy 30 20" -> a Pending with its numbers, for the calls the
// plot draws; nullopt for others, or (with a note) for numbers it cannot use.
std::optional<Pending> guidance_call(std::string_view message, double t, const Place& at, MissionPlot& plot) {
  std::istringstream words{std::string(message)};
  std::string verb;
  Pending call;
  call.time_s = t;
  if (!(words >> verb >> call.name) || verb != "exec") return std::nullopt;
  std::size_t arity = 0;
  if (call.name == "goto_xy") {
    arity = 2;
  } else if (call.name == "track") {
    arity = 4;
  } else if (call.name != "gps_fix") {
    return std::nullopt;
  }
  std::string word;
  while (words >> word) {
    char* end = nullptr;
    const double v = std::strtod(word.c_str(), &end);
    if (end != word.c_str() + word.size() || !drawable(v)) {
      note(plot, at, fmt::format("request: '{}': '{}' is not a coordinate: skipped", message, word));
      return std::nullopt;
    }
    call.args.push_back(v);
  }
  if (call.args.size() != arity) {
    note(plot, at, fmt::format("request: '{}': {} takes {} numbers: skipped", message, call.name, arity));
    return std::nullopt;
  }
  return call;
}

// The position of `path` at `t`: the last sample at or before it; with
// `after`, the first at or after it, else the last before. A linear scan: a
// hostile log's times need not be in order.
std::optional<Point> position_at(const Path& path, double t, bool after) {
  std::optional<Point> before;
  for (std::size_t i = 0; i < path.size(); ++i) {
    if (after && path.time_s[i] >= t) return path.at[i];
    if (path.time_s[i] <= t) before = path.at[i];
  }
  return before;
}

// Reads one event into `plot`.
core::Result<void> read_event(const json& e, const Place& at, MissionPlot& plot, ReadState& state) {
  auto& open = state.open;
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
    auto altitude = number(e, "altitude_m", at);
    if (!altitude) return altitude.error();
    if (altitude.value() && !drawable(*altitude.value())) {
      note(
          plot, at,
          fmt::format("telemetry: altitude_m {} is beyond {} km: skipped", *altitude.value(), kMaxCoordinate_m / 1000));
    } else if (altitude.value()) {
      plot.altitude_m.time_s.push_back(t.value());
      plot.altitude_m.value.push_back(*altitude.value());
      auto depth = number(e, "depth_m", at);  // its type was checked above
      if (depth.value() && drawable(*depth.value())) {
        plot.seabed_m.time_s.push_back(t.value());
        plot.seabed_m.value.push_back(*depth.value() + *altitude.value());
      }
    }
    auto estimated = read_pair(e, "x_m", "y_m", t.value(), at, plot, plot.estimated);
    if (!estimated) return estimated;
    auto truth = read_pair(e, "true_x_m", "true_y_m", t.value(), at, plot, plot.truth);
    if (!truth) return truth;
  } else if (event == "request") {
    // Only the calls the plot draws are read: a tank log's requests, or
    // their oddities, change nothing.
    auto message = e.find("message");
    if (message == e.end() || !message->is_string()) return {};
    auto call = guidance_call(message->get_ref<const std::string&>(), time.value().value_or(0.0), at, plot);
    if (!call) return {};
    auto t = need_time();
    if (!t) return t.error();
    auto id = count(e, "id", at);
    if (!id) return id.error();
    state.pending[id.value()] = std::move(*call);
  } else if (event == "reply") {
    auto id = e.find("id");
    if (id == e.end() || !id->is_number_unsigned()) return {};
    auto it = state.pending.find(id->get<std::uint64_t>());
    if (it == state.pending.end()) return {};
    auto t = need_time();
    if (!t) return t.error();
    const Pending call = std::move(it->second);
    state.pending.erase(it);
    auto result = e.find("result");
    if (result == e.end() || !result->is_number() || result->get<double>() != 1.0) return {};  // refused
    const auto& a = call.args;
    if (call.name == "gps_fix") {
      plot.fixes.push_back({t.value(), {}});
    } else if (call.name == "track") {
      plot.plan.push_back({call.time_s, true, true, {a[0], a[1]}, {a[2], a[3]}});
    } else {
      plot.plan.push_back({call.time_s, false, true, {}, {a[0], a[1]}});
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
  ReadState state;
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
    auto read = read_event(e, at, plot, state);
    if (!read) return read.error();
  }
  if (in.bad()) return core::make_error(core::ErrorCode::Io, fmt::format("cannot read '{}'", name));
  if (plot.depth_m.empty()) {
    return core::make_error(core::ErrorCode::InvalidInput,
                            fmt::format("{}: no telemetry with depth_m: nothing to plot", name));
  }
  // A phase still running when the log stops is drawn to the log's end.
  for (const auto& [instance, index] : state.open) plot.phases[index].end_s = plot.last_s;
  // Where the legs start and the fixes are, now that the whole track is read.
  for (PlannedLeg& leg : plot.plan) {
    if (leg.track) continue;
    auto from = position_at(plot.estimated, leg.time_s, false);
    leg.from_known = from.has_value();
    if (from) leg.from = *from;
  }
  std::erase_if(plot.fixes, [&](Fix& fix) {
    auto where = position_at(plot.estimated, fix.time_s, true);
    if (where) fix.at = *where;
    return !where;
  });
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
