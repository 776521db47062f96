#pragma once
// Everything a run tells the outside, through one interface: the Strategic
// level's events (strategic::Observer: phases, firings, actions, the
// executor's end), the Tactical level's telemetry and REPORTs, the vehicle's
// events, the run's own notes, and the run's end with its report. The
// console, the studio and tests are RunObservers; the mission log is written
// by the run itself.
//
// Threads: every call comes on the run's event-loop thread, in order. An
// observer must not call back into the run (RunSession::stop() excepted).
#include <optional>
#include <string>

#include "protocol/message.h"
#include "run/report.h"
#include "strategic/executor.h"

namespace strata::run {

class RunObserver : public strategic::Observer {
 public:
  virtual void telemetry(const protocol::Telemetry&) {}
  virtual void report(const std::string& /*text*/, double /*sim_time_s*/) {}
  virtual void vehicle_event(const std::string& /*text*/, double /*sim_time_s*/) {}
  // A line from the run itself ("vehicle phoenix-sim in this process ...", what the safe
  // end does), with the simulated time when it has one.
  virtual void note(const std::string& /*text*/, std::optional<double> /*sim_time_s*/) {}
  // Last: the run is over and its log closed. Told even when the mission
  // never started (report.result unset).
  virtual void run_ended(const RunReport&) {}
};

}  // namespace strata::run
