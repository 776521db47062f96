#include "studio/run_publisher.h"

#include "petri/state.h"

namespace strata::studio {

nlohmann::json marking_json(const petri::State& state) {
  nlohmann::json m = nlohmann::json::object();
  const petri::Net& net = state.net();
  for (petri::PlaceId p = 0; p < net.place_count(); ++p) {
    if (state.marking()[p] > 0) m[std::string(net.place_name(p))] = state.marking()[p];
  }
  return m;
}

void RunPublisher::phase_started(const strategic::PhaseStart& e) {
  nlohmann::json marking = e.state ? marking_json(*e.state) : nlohmann::json::object();
  markings_[e.instance] = marking;
  nets_[e.instance] = std::string(e.name);
  hub_.publish("phase_start", {{"instance", e.instance}, {"parent", e.parent}, {"net", e.name}, {"caller", e.caller},
                               {"depth", e.depth}, {"marking", marking}, {"t", e.sim_time_s}});
}

void RunPublisher::phase_ended(const strategic::PhaseEnd& e) {
  markings_.erase(e.instance);
  nets_.erase(e.instance);
  hub_.publish("phase_end", {{"instance", e.instance}, {"net", e.name}, {"exit", e.exit}, {"cancelled", e.cancelled},
                             {"t", e.sim_time_s}});
}

void RunPublisher::fired(const strategic::Firing& e) {
  nlohmann::json marking = e.state ? marking_json(*e.state) : nlohmann::json::object();
  nlohmann::json enabled = nlohmann::json::array();
  if (e.state) {
    for (petri::TransitionId t : e.state->enabled().sorted()) enabled.push_back(e.state->net().transition_name(t));
  }
  markings_[e.instance] = marking;
  hub_.publish("fired", {{"instance", e.instance}, {"net", e.net}, {"transition", e.transition_name},
                         {"marking", marking}, {"enabled", enabled}, {"index", e.index}, {"t", e.sim_time_s}});
}

void RunPublisher::action_started(const strategic::ActionStart& e) {
  hub_.publish("action_start", {{"id", e.id}, {"instance", e.instance}, {"transition", e.transition}, {"kind", e.kind},
                                {"primitive", e.primitive}, {"t", e.sim_time_s}});
}

void RunPublisher::action_finished(const strategic::ActionFinish& e) {
  nlohmann::json& marking = markings_[e.instance];
  if (!marking.is_object()) marking = nlohmann::json::object();
  if (!e.marks.empty()) marking[std::string(e.marks)] = marking.value(std::string(e.marks), 0) + 1;
  hub_.publish("action_finish", {{"id", e.id}, {"instance", e.instance}, {"primitive", e.primitive}, {"value", e.value},
                                 {"marks", e.marks}, {"marking", marking}, {"t", e.sim_time_s}});
}

void RunPublisher::mission_ended(const strategic::MissionResult& r) {
  hub_.publish("run_end", {{"outcome", strategic::to_string(r.outcome)}, {"exit", r.exit}, {"reason", r.reason},
                           {"t", r.sim_time_s}});
}

void RunPublisher::telemetry(double t, double depth_m, std::optional<double> setpoint_m) {
  hub_.publish("telemetry", {{"t", t}, {"depth", depth_m}, {"setpoint", setpoint_m ? nlohmann::json(*setpoint_m) : nlohmann::json(nullptr)}});
}

void RunPublisher::report(double t, const std::string& text) { hub_.publish("report", {{"t", t}, {"text", text}}); }

}  // namespace strata::studio
