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
// In flight, as the engine has it: a REPORT is sent and not waited for, so
// its action_start is followed at once by its action_finish; a phase's end
// (phase_end, with "action": the PHASE action that ran it) ends that PHASE
// action and every action its net still had in flight; when the phase exits
// normally, the mark it makes in its caller comes as action_finish with the
// PHASE action's id (the engine tells it with id 0).
//
// run_end carries the phase the run ended in ("phase": the deepest phase
// still running when the mission ended, else the last phase that took a
// later exit than its first, else "").
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
  // The run's mission log, relative to the studio's folder, for run_end's
  // "log" ("" none).
  void set_log(std::string relative) { log_ = std::move(relative); }

  void phase_started(const strategic::PhaseStart& e) override;
  void phase_ended(const strategic::PhaseEnd& e) override;
  void fired(const strategic::Firing& e) override;
  void action_started(const strategic::ActionStart& e) override;
  void action_finished(const strategic::ActionFinish& e) override;
  void guard_tripped(const strategic::GuardTrip& e) override;
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
  // Actions in flight (not REPORTs) and the instance that issued them.
  std::map<strategic::ActionId, strategic::InstanceId> in_flight_;
  // The PHASE action that started each instance; the last PHASE action
  // started (its instance's phase_started comes right after).
  std::map<strategic::InstanceId, strategic::ActionId> phase_action_;
  strategic::ActionId pending_phase_action_ = 0;
  // The PHASE action of the phase that just exited: the engine's next
  // ActionFinish with id 0 is its mark in the caller.
  strategic::ActionId exited_phase_action_ = 0;
  std::map<strategic::InstanceId, std::size_t> depth_;
  std::string deepest_cancelled_;  // the phase the mission ended in, if it was cut short
  std::size_t deepest_cancelled_depth_ = 0;
  std::string last_aborted_phase_;  // the last phase that took a later exit
  std::string log_;
};

// Only the places holding tokens: {"start": 1}.
nlohmann::json marking_json(const petri::State& state);
nlohmann::json marking_json(const RunPublisher::Names& names, const petri::Marking& marking);

}  // namespace strata::studio
