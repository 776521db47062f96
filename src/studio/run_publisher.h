#pragma once
// A run::RunObserver that tells the EventHub what a run does, in the events
// of docs/studio.md: phases, firings (with the marking after, and the
// enabled transitions), actions in flight, telemetry, reports, and the run's
// end once its safe end is over.
//
// Cost to the run: each event captures what it needs (a marking is a copy of
// the net's token vector, names are shared per instance) and its JSON is
// built later, by whoever reads it first (EventHub::publish_lazy).
//
// Threads: called on the run's event-loop thread; the hub is thread-safe.
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "petri/net.h"
#include "run/observer.h"
#include "strategic/executor.h"
#include "studio/event_hub.h"

namespace strata::studio {

class RunPublisher final : public run::RunObserver {
 public:
  explicit RunPublisher(EventHub& hub) : hub_(hub) {}

  void phase_started(const strategic::PhaseStart& e) override;
  void phase_ended(const strategic::PhaseEnd& e) override;
  void fired(const strategic::Firing& e) override;
  void action_started(const strategic::ActionStart& e) override;
  void action_finished(const strategic::ActionFinish& e) override;
  void telemetry(const protocol::Telemetry& t) override;
  void report(const std::string& text, double sim_time_s) override;
  void run_ended(const run::RunReport& report) override;

  // The names of one net's places and transitions, kept past the run.
  struct Names {
    std::vector<std::string> places, transitions;
  };

 private:
  struct Running {
    std::shared_ptr<const Names> names;
    petri::Marking marking;  // as last told
  };
  EventHub& hub_;
  std::map<strategic::InstanceId, Running> running_;
};

// Only the places holding tokens: {"start": 1}.
nlohmann::json marking_json(const petri::State& state);
nlohmann::json marking_json(const RunPublisher::Names& names, const petri::Marking& marking);

}  // namespace strata::studio
