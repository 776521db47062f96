#include "studio/replay.h"

#include <map>
#include <sstream>

#include <fmt/format.h>

namespace strata::studio {
namespace {

void add(nlohmann::json& marking, const nlohmann::json& delta, int sign) {
  if (!delta.is_object()) return;
  for (const auto& [place, n] : delta.items()) {
    const std::int64_t now = marking.value(place, std::int64_t{0}) + sign * n.get<std::int64_t>();
    if (now > 0) {
      marking[place] = now;
    } else {
      marking.erase(place);
    }
  }
}

}  // namespace

core::Result<nlohmann::json> replay_from_log(const std::string& text) {
  nlohmann::json events = nlohmann::json::array();
  std::map<std::uint64_t, nlohmann::json> markings;
  std::string mission;
  std::istringstream in(text);
  std::string line;
  for (std::size_t n = 1; std::getline(in, line); ++n) {
    if (line.empty()) continue;
    nlohmann::json e = nlohmann::json::parse(line, nullptr, false);
    if (e.is_discarded() || !e.is_object()) {
      return core::Error{core::ErrorCode::InvalidInput, fmt::format("line {} of the log is not a JSON event", n)};
    }
    const std::string kind = e.value("event", "");
    const double t = e.value("sim_time", 0.0);
    const std::uint64_t instance = e.value("instance", std::uint64_t{0});
    auto emit = [&](const char* name, nlohmann::json data) {
      data["t"] = t;
      events.push_back({{"event", name}, {"data", std::move(data)}});
    };
    if (kind == "run") {
      mission = e.value("mission", "");
    } else if (kind == "phase_start") {
      markings[instance] = e.value("marking", nlohmann::json::object());
      emit("phase_start", {{"instance", instance},
                           {"parent", e.value("parent", 0)},
                           {"net", e.value("net", "")},
                           {"caller", e.value("caller", "")},
                           {"depth", e.value("depth", 0)},
                           {"marking", markings[instance]}});
    } else if (kind == "fire") {
      nlohmann::json& m = markings[instance];
      if (!m.is_object()) m = nlohmann::json::object();
      add(m, e.value("consumed", nlohmann::json::object()), -1);
      add(m, e.value("produced", nlohmann::json::object()), +1);
      emit("fired", {{"instance", instance},
                     {"net", e.value("net", "")},
                     {"transition", e.value("transition", "")},
                     {"marking", m},
                     {"index", e.value("n", 0)}});
    } else if (kind == "mark") {
      nlohmann::json& m = markings[instance];
      if (!m.is_object()) m = nlohmann::json::object();
      add(m, nlohmann::json{{e.value("place", ""), 1}}, +1);
      emit("action_finish",
           {{"instance", instance}, {"primitive", e.value("by", "")}, {"marks", e.value("place", "")}, {"marking", m}});
    } else if (kind == "guard_tripped") {
      emit("report", {{"text", fmt::format("guard {} of {} tripped ({})", e.value("guard", ""), e.value("net", ""),
                                           e.value("condition", ""))}});
    } else if (kind == "phase_end") {
      markings.erase(instance);
      emit("phase_end", {{"instance", instance}, {"net", e.value("net", "")}, {"exit", e.value("exit", "")}});
    } else if (kind == "telemetry") {
      nlohmann::json d = {{"depth", e.value("depth_m", 0.0)},
                          {"setpoint", e.contains("setpoint_m") ? e["setpoint_m"] : nlohmann::json(nullptr)}};
      // The estimated position, where the log has one (open water), for the map.
      if (e.contains("x_m") && e.contains("y_m") && e["x_m"].is_number() && e["y_m"].is_number()) {
        d["x"] = e["x_m"];
        d["y"] = e["y_m"];
      }
      emit("telemetry", std::move(d));
    } else if (kind == "report") {
      emit("report", {{"text", e.value("text", "")}});
    } else if (kind == "scripted_answer") {
      // `strata run --answers`: a call the script answered, and what the
      // vehicle itself said (docs/mission-log.md).
      emit("scripted_answer", {{"answer_index", e.value("answer_index", 0)},
                               {"step", e.value("step", 0)},
                               {"net", e.value("net", "")},
                               {"transition", e.value("transition", "")},
                               {"action", e.value("action", "")},
                               {"primitive", e.value("primitive", "")},
                               {"vehicle", e.value("vehicle", 0)},
                               {"answer", e.value("answer", 0)}});
    } else if (kind == "scripted_phase") {
      emit("scripted_phase", {{"answer_index", e.value("answer_index", 0)},
                              {"step", e.value("step", 0)},
                              {"net", e.value("net", "")},
                              {"transition", e.value("transition", "")},
                              {"phase", e.value("phase", "")},
                              {"exit", e.value("exit", "")}});
    } else if (kind == "answers_diverged") {
      emit("answers_diverged", {{"reason", e.value("reason", "")}, {"used", e.value("used", 0)}});
    } else if (kind == "mission_end") {
      emit("run_end", {{"outcome", e.value("outcome", "")},
                       {"exit", e.value("exit", "")},
                       {"reason", e.value("reason", "")},
                       {"mission_t", e.value("mission_sim_time", t)}});
    }
  }
  return nlohmann::json{{"mission", mission}, {"events", events}};
}

}  // namespace strata::studio
