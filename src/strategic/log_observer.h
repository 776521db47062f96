#pragma once
// Writes what the Strategic level does into the mission log, beside the
// Tactical level's request/reply lines:
//   {"event":"phase_start","instance","net","parent","caller","depth","marking","sim_time"}
//   {"event":"fire","n","instance","net","transition","consumed","produced","sim_time"}
//   {"event":"mark","instance","net","place","by","sim_time"}      (a reply marked a place)
//   {"event":"phase_end","instance","net","exit","result","sim_time"} (result: completed |
//                                                                  aborted | cancelled)
//   {"event":"notice","text","sim_time"}
//   {"event":"guard_tripped","instance","net","guard","condition","preempted_phases","preempted_calls","sim_time"}
// The run writes the last lines itself, after its safe end (run/session.h):
//   {"event":"mission_end","outcome","exit","reason",["stopped_by"],["safe_end"],"exit_code","sim_time"}
// consumed/produced/marking are objects {place: tokens} in declaration order.
// Together with the header these replay a run's markings exactly.
#include "strategic/executor.h"
#include "tactical/mission_log.h"

namespace strata::strategic {

class LogObserver final : public Observer {
 public:
  // log must outlive this observer.
  explicit LogObserver(tactical::MissionLog& log) : log_(log) {}

  void phase_started(const PhaseStart& e) override;
  void phase_ended(const PhaseEnd& e) override;
  void fired(const Firing& e) override;
  void action_finished(const ActionFinish& e) override;
  void notice(const Notice& e) override;
  void guard_tripped(const GuardTrip& e) override;

 private:
  tactical::MissionLog& log_;
};

}  // namespace strata::strategic
