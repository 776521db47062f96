#pragma once
// A strategic::Observer that tells the EventHub what a run does, in the
// events of docs/studio.md: phases, firings (with the marking after, and the
// enabled transitions), actions in flight, the end. Telemetry and reports
// come from the Tactical level, through telemetry() and report().
//
// Threads: called on the run's event-loop thread; the hub is thread-safe.
#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "strategic/executor.h"
#include "studio/event_hub.h"

namespace strata::studio {

class RunPublisher final : public strategic::Observer {
 public:
  explicit RunPublisher(EventHub& hub) : hub_(hub) {}

  void phase_started(const strategic::PhaseStart& e) override;
  void phase_ended(const strategic::PhaseEnd& e) override;
  void fired(const strategic::Firing& e) override;
  void action_started(const strategic::ActionStart& e) override;
  void action_finished(const strategic::ActionFinish& e) override;
  void mission_ended(const strategic::MissionResult& r) override;

  void telemetry(double t, double depth_m, std::optional<double> setpoint_m);
  void report(double t, const std::string& text);

 private:
  EventHub& hub_;
  // The marking of each running instance, by place name, for action_finish
  // (which carries only the place a reply marked).
  std::map<strategic::InstanceId, nlohmann::json> markings_;
  std::map<strategic::InstanceId, std::string> nets_;
};

// Only the places holding tokens: {"start": 1}.
nlohmann::json marking_json(const petri::State& state);

}  // namespace strata::studio
