#include "strategic/log_observer.h"

#include "petri/state.h"

namespace strata::strategic {
namespace {

using Json = nlohmann::ordered_json;

// {"place": tokens, ...} in the order given. A place named twice keeps its
// first place and its last count, as a JSON object built key by key would.
void tokens_object(tactical::LogLine& line, std::string_view key,
                   const std::vector<std::pair<std::string_view, petri::Tokens>>& changes) {
  line.begin_object(key);
  for (std::size_t i = 0; i < changes.size(); ++i) {
    const std::string_view place = changes[i].first;
    bool seen_before = false;
    for (std::size_t j = 0; j < i && !seen_before; ++j) seen_before = changes[j].first == place;
    if (seen_before) continue;
    petri::Tokens n = changes[i].second;
    for (std::size_t j = i + 1; j < changes.size(); ++j) {
      if (changes[j].first == place) n = changes[j].second;
    }
    line.add(place, n);
  }
  line.end_object();
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
  tactical::LogLine line("fire");
  line.add("n", e.index).add("instance", e.instance).add("net", e.net).add("transition", e.transition_name);
  tokens_object(line, "consumed", e.consumed);
  tokens_object(line, "produced", e.produced);
  line.add("sim_time", t(e.sim_time_s));
  log_.write(std::move(line));
}

void LogObserver::action_finished(const ActionFinish& e) {
  if (e.marks.empty()) return;
  tactical::LogLine line("mark");
  line.add("instance", e.instance).add("net", e.net).add("place", e.marks).add("by", e.primitive);
  line.add("sim_time", t(e.sim_time_s));
  log_.write(std::move(line));
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
