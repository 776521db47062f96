#include "strategic/log_observer.h"

#include "petri/state.h"

namespace strata::strategic {
namespace {

using Json = nlohmann::ordered_json;

Json tokens_object(const std::vector<std::pair<std::string_view, petri::Tokens>>& changes) {
  Json out = Json::object();
  for (const auto& [place, n] : changes) out[std::string(place)] = n;
  return out;
}

Json marking_object(const petri::State& state) {
  Json out = Json::object();
  const petri::Net& net = state.net();
  for (petri::PlaceId p = 0; p < net.place_count(); ++p) {
    if (state.tokens(p) > 0) out[std::string(net.place_name(p))] = state.tokens(p);
  }
  return out;
}

double t(double sim_time_s) { return tactical::log_time(sim_time_s); }

}  // namespace

void LogObserver::phase_started(const PhaseStart& e) {
  Json line;
  line["event"] = "phase_start";
  line["instance"] = e.instance;
  line["net"] = e.name;
  line["parent"] = e.parent;
  line["caller"] = e.caller;
  line["depth"] = e.depth;
  if (e.state) line["marking"] = marking_object(*e.state);
  line["sim_time"] = t(e.sim_time_s);
  log_.write(line);
}

void LogObserver::phase_ended(const PhaseEnd& e) {
  Json line;
  line["event"] = "phase_end";
  line["instance"] = e.instance;
  line["net"] = e.name;
  line["exit"] = e.exit;
  line["result"] = e.cancelled ? "cancelled" : e.exit_index == 0 ? "completed" : "aborted";
  line["sim_time"] = t(e.sim_time_s);
  log_.write(line);
}

void LogObserver::fired(const Firing& e) {
  Json line;
  line["event"] = "fire";
  line["n"] = e.index;
  line["instance"] = e.instance;
  line["net"] = e.net;
  line["transition"] = e.transition_name;
  line["consumed"] = tokens_object(e.consumed);
  line["produced"] = tokens_object(e.produced);
  line["sim_time"] = t(e.sim_time_s);
  log_.write(line);
}

void LogObserver::action_finished(const ActionFinish& e) {
  if (e.marks.empty()) return;
  Json line;
  line["event"] = "mark";
  line["instance"] = e.instance;
  line["net"] = e.net;
  line["place"] = e.marks;
  line["by"] = e.primitive;
  line["sim_time"] = t(e.sim_time_s);
  log_.write(line);
}

void LogObserver::notice(const Notice& e) {
  Json line;
  line["event"] = "notice";
  line["text"] = e.text;
  line["sim_time"] = t(e.sim_time_s);
  log_.write(line);
}

void LogObserver::guard_tripped(const GuardTrip& e) {
  Json line;
  line["event"] = "guard_tripped";
  line["instance"] = e.instance;
  line["net"] = e.net;
  line["guard"] = e.guard;
  line["condition"] = e.condition;
  line["preempted_phases"] = e.preempted_phases;
  line["preempted_calls"] = e.preempted_calls;
  line["sim_time"] = t(e.sim_time_s);
  log_.write(line);
}

}  // namespace strata::strategic
