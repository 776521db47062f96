#include "studio/run_publisher.h"

#include <algorithm>

#include <charconv>
#include <cmath>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "petri/state.h"

namespace strata::studio {

using nlohmann::json;

json marking_json(const RunPublisher::Names& names, const petri::Marking& marking) {
  json m = json::object();
  for (std::size_t p = 0; p < marking.size() && p < names.places.size(); ++p) {
    if (marking[p] > 0) m[names.places[p]] = marking[p];
  }
  return m;
}

json marking_json(const petri::State& state) {
  json m = json::object();
  const petri::Net& net = state.net();
  for (petri::PlaceId p = 0; p < net.place_count(); ++p) {
    if (state.marking()[p] > 0) m[std::string(net.place_name(p))] = state.marking()[p];
  }
  return m;
}

void RunPublisher::phase_started(const strategic::PhaseStart& e) {
  if (e.depth > 0 && pending_phase_action_ != 0) {
    phase_action_[e.instance] = pending_phase_action_;
    pending_phase_action_ = 0;
  }
  depth_[e.instance] = e.depth;
  auto names = std::make_shared<Names>();
  Running& r = running_[e.instance];
  if (e.state) {
    const petri::Net& net = e.state->net();
    for (petri::PlaceId p = 0; p < net.place_count(); ++p) names->places.emplace_back(net.place_name(p));
    for (petri::TransitionId t = 0; t < net.transition_count(); ++t)
      names->transitions.emplace_back(net.transition_name(t));
    r.marking = e.state->marking();
  }
  r.names = names;
  hub_.publish_lazy("phase_start", {e.instance, 0},
                    [names, marking = r.marking, instance = e.instance, parent = e.parent, net = std::string(e.name),
                     caller = std::string(e.caller), depth = e.depth, t = e.sim_time_s] {
                      return json{{"instance", instance},
                                  {"parent", parent},
                                  {"net", net},
                                  {"caller", caller},
                                  {"depth", depth},
                                  {"marking", marking_json(*names, marking)},
                                  {"t", t}};
                    });
}

void RunPublisher::phase_ended(const strategic::PhaseEnd& e) {
  running_.erase(e.instance);
  strategic::ActionId action = 0;
  if (auto it = phase_action_.find(e.instance); it != phase_action_.end()) {
    action = it->second;
    phase_action_.erase(it);
  }
  // What the engine dropped with the phase: the PHASE action, and the
  // actions of its net still waiting for a reply.
  std::vector<strategic::ActionId> dropped;
  for (auto it = in_flight_.begin(); it != in_flight_.end();) {
    if (it->second == e.instance || it->first == action) {
      if (it->first != action) dropped.push_back(it->first);
      it = in_flight_.erase(it);
    } else {
      ++it;
    }
  }
  exited_phase_action_ = e.cancelled ? 0 : action;
  const std::size_t depth = depth_.count(e.instance) ? depth_[e.instance] : 0;
  depth_.erase(e.instance);
  if (depth > 0) {
    if (e.cancelled && depth > deepest_cancelled_depth_) {
      deepest_cancelled_depth_ = depth;
      deepest_cancelled_ = std::string(e.name);
    } else if (!e.cancelled && e.exit_index != 0) {
      last_aborted_phase_ = std::string(e.name);
    }
  }
  EventHub::Keys keys{e.instance, action, std::string(e.name)};
  hub_.publish_lazy("phase_end", keys,
                    [instance = e.instance, net = std::string(e.name), exit = std::string(e.exit),
                     cancelled = e.cancelled, action, dropped = std::move(dropped), t = e.sim_time_s] {
                      return json{
                          {"instance", instance}, {"net", net},         {"exit", exit}, {"cancelled", cancelled},
                          {"action", action},     {"dropped", dropped}, {"t", t}};
                    });
}

void RunPublisher::fired(const strategic::Firing& e) {
  Running& r = running_[e.instance];
  std::vector<petri::TransitionId> enabled;
  if (e.state) {
    r.marking = e.state->marking();
    enabled = e.state->enabled().sorted();
  }
  hub_.publish_lazy(
      "fired", {e.instance, 0},
      [names = r.names, marking = r.marking, enabled = std::move(enabled), instance = e.instance,
       net = std::string(e.net), transition = std::string(e.transition_name), index = e.index, t = e.sim_time_s] {
        json on = json::array();
        for (auto id : enabled) {
          if (names && id < names->transitions.size()) on.push_back(names->transitions[id]);
        }
        return json{{"instance", instance},
                    {"net", net},
                    {"transition", transition},
                    {"marking", names ? marking_json(*names, marking) : json::object()},
                    {"enabled", on},
                    {"index", index},
                    {"t", t}};
      });
}

void RunPublisher::action_started(const strategic::ActionStart& e) {
  hub_.publish_lazy("action_start", {e.instance, e.id},
                    [id = e.id, instance = e.instance, transition = std::string(e.transition),
                     kind = std::string(e.kind_name()), primitive = std::string(e.primitive), t = e.sim_time_s] {
                      return json{{"id", id},     {"instance", instance},   {"transition", transition},
                                  {"kind", kind}, {"primitive", primitive}, {"t", t}};
                    });
  if (e.is_call(core::CallVerb::Report)) {
    // Sent, never answered: not in flight once sent.
    Running& r = running_[e.instance];
    hub_.publish_lazy("action_finish", {e.instance, e.id},
                      [names = r.names, marking = r.marking, id = e.id, instance = e.instance,
                       primitive = std::string(e.primitive), t = e.sim_time_s] {
                        return json{{"id", id},
                                    {"instance", instance},
                                    {"primitive", primitive},
                                    {"value", true},
                                    {"marks", ""},
                                    {"marking", names ? marking_json(*names, marking) : json::object()},
                                    {"t", t}};
                      });
    return;
  }
  in_flight_[e.id] = e.instance;
  if (e.is_phase()) pending_phase_action_ = e.id;
}

void RunPublisher::action_finished(const strategic::ActionFinish& ev) {
  strategic::ActionFinish e = ev;
  if (e.id == 0 && exited_phase_action_ != 0) e.id = exited_phase_action_;  // a phase's exit marking its caller
  exited_phase_action_ = 0;
  in_flight_.erase(e.id);
  Running& r = running_[e.instance];
  if (!e.marks.empty() && r.names) {
    for (std::size_t p = 0; p < r.names->places.size() && p < r.marking.size(); ++p) {
      if (r.names->places[p] == e.marks) {
        ++r.marking[p];
        break;
      }
    }
  }
  hub_.publish_lazy(
      "action_finish", {e.instance, e.id},
      [names = r.names, marking = r.marking, id = e.id, instance = e.instance, primitive = std::string(e.primitive),
       value = e.value, marks = std::string(e.marks), t = e.sim_time_s] {
        return json{{"id", id},
                    {"instance", instance},
                    {"primitive", primitive},
                    {"value", value},
                    {"marks", marks},
                    {"marking", names ? marking_json(*names, marking) : json::object()},
                    {"t", t}};
      });
}

// After the safe end, with the run's own word on how it ended. A run that
// never started is told by the StudioRunner, with what went wrong.
void RunPublisher::run_ended(const run::RunReport& report) {
  if (!report.result) return;
  const strategic::MissionResult& r = *report.result;
  hub_.publish("run_end", {{"outcome", strategic::to_string(r.outcome)},
                           {"exit", r.exit},
                           {"reason", r.reason},
                           {"phase", !deepest_cancelled_.empty() ? deepest_cancelled_ : last_aborted_phase_},
                           {"stopped_by", report.stopped_by},
                           {"stop", report.stop_mode},
                           {"exit_code", report.exit_code},
                           {"final_depth_m", report.final_depth_m ? json(*report.final_depth_m) : json(nullptr)},
                           {"surfaced", report.emergency_surfaced},
                           {"log", log_},
                           // The run's end, after the safe end (the replay's too); the
                           // mission's own end is mission_t.
                           {"t", std::max({r.sim_time_s, report.sim_time_s, report.final_time_s.value_or(0.0)})},
                           {"mission_t", r.sim_time_s}});
}

namespace {

// An extra field of the telemetry line as a finite number, if it is one.
std::optional<double> extra_number(const protocol::Telemetry& sample, const std::string& key) {
  const auto it = sample.extras.find(key);
  if (it == sample.extras.end()) return std::nullopt;
  double v = 0.0;
  const char* end = it->second.data() + it->second.size();
  const auto [ptr, ec] = std::from_chars(it->second.data(), end, v);
  if (ec != std::errc{} || ptr != end || !std::isfinite(v)) return std::nullopt;
  return v;
}

}  // namespace

void RunPublisher::telemetry(const protocol::Telemetry& sample) {
  const double t = sample.sim_time_s;
  const double depth_m = sample.depth_m.value_or(0.0);
  const std::optional<double> setpoint_m = sample.setpoint_m;
  // The vehicle's estimated position (open water only; the map panel draws
  // it). A tank run's samples have none, and leave x and y out.
  const std::optional<double> x_m = extra_number(sample, "x");
  const std::optional<double> y_m = extra_number(sample, "y");
  hub_.publish_lazy("telemetry", {}, [t, depth_m, setpoint_m, x_m, y_m] {
    json out{{"t", t}, {"depth", depth_m}, {"setpoint", setpoint_m ? json(*setpoint_m) : json(nullptr)}};
    if (x_m && y_m) {
      out["x"] = *x_m;
      out["y"] = *y_m;
    }
    return out;
  });
}

void RunPublisher::guard_tripped(const strategic::GuardTrip& e) {
  // Shown in the page's log as the run's reports are.
  report(fmt::format("guard {} of {} tripped ({})", e.guard, e.net, e.condition), e.sim_time_s);
}

void RunPublisher::report(const std::string& text, double t) {
  hub_.publish_lazy("report", {}, [t, text] { return json{{"t", t}, {"text", text}}; });
}

}  // namespace strata::studio
