#pragma once
// The PROLOG Strategic level (paper §2.2, Figure 10; docs/prolog.md): runs a
// mission's rules (PrologMission) through the same Tactics interface and
// the same observers as the CORAL Engine. A primitive call yields the
// rules back to the event loop; the vehicle's answer resumes them.
//
// How a mission ends (docs/prolog.md §3):
//  - mission/0 succeeds: Completed, or Aborted when
//    current_phase(mission_abort) holds (Figure 10's `done`).
//  - the rules call halt/0 or halt/1, at any moment: Aborted ("the rules
//    called halt", "... halt(N)"); the run's end path surfaces the vehicle.
//  - Failed: mission/0 fails or raises; a primitive call fails; EXEC or OOD
//    is answered 0 (as in CORAL); the rules run more than inference_limit
//    inferences between two primitive calls (an endless loop) or out of
//    stack (endless recursion); cancel(); interrupt().
//
// Threads: the thread that prolog::initialised SWI-Prolog, which runs the event
// loop, for everything but interrupt() (any thread). One PROLOG mission
// runs at a time per process, and a loaded PrologMission runs once: a
// second executor started meanwhile, or on rules that have run, ends
// Failed at once and says why.
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "strategic/prolog_mission.h"
#include "strategic/executor.h"
#include "strategic/tactics.h"

namespace strata::strategic {

struct PrologOptions {
  // Inferences the rules may make between two primitive calls; a mission's
  // rules make a few hundred. 10 M is about half a second of pure Prolog.
  std::uint64_t inference_limit = 10'000'000;
};

class PrologExecutor final : public ExecutorBase, private PrologHost {
 public:
  // mission, tactics and catalogue must outlive the executor.
  PrologExecutor(PrologMission& mission, Tactics& tactics, const tactical::Catalogue& catalogue,
                 PrologOptions options = {});
  ~PrologExecutor() override;
  PrologExecutor(const PrologExecutor&) = delete;
  PrologExecutor& operator=(const PrologExecutor&) = delete;

  void start(std::function<void(const MissionResult&)> on_end) override;
  void cancel(std::string reason) override;
  // Any thread. Rules that run (computing, in sleep/1, in a loop, inside a
  // catch-all) stop within milliseconds (interrupt_rules()) and the
  // mission ends Failed with reason, from the loop. Rules that wait for the
  // vehicle are not disturbed: the caller's posted cancel ends the mission,
  // or the reply does if it comes first. From the interrupt on the rules
  // never run again.
  void interrupt(const std::string& reason) override;

 private:
  struct Phase {
    InstanceId instance = 0;
    std::string name;
  };

  // PrologHost
  void primitive(const std::string& name, std::vector<tactical::Value> args) override;
  std::optional<int> answer() override { return answer_; }
  void report(const std::string& name, std::vector<tactical::Value> args) override;
  void phase_started(const std::string& phase) override;
  void phase_ended(const std::string& phase, const std::string& exit) override;

  void resume();  // runs the rules until they yield or end
  void issue();   // sends the call the rules just made
  void deliver(ActionId id, tactical::CallResult outcome);
  void rules_ended();
  void fail(std::string reason, std::optional<tactical::CallError::Kind> call_error = std::nullopt);
  // The reason interrupt() gave, once it was called on the running executor.
  std::optional<std::string> interrupt_reason() const;
  // finish()'s part: the engine let go, the phases still running end
  // (innermost first), then the mission's own phase.
  void wind_down(const MissionResult& result) override;
  double now() const { return tactics_.sim_time_s(); }
  InstanceId current_instance() const { return phases_.empty() ? 0 : phases_.back().instance; }

  PrologMission& mission_;
  Tactics& tactics_;
  const tactical::Catalogue& catalogue_;
  PrologOptions options_;
  std::unique_ptr<PrologMissionQuery> query_;
  std::shared_ptr<PrologExecutor*> self_;

  // Shared with interrupt()'s thread.
  mutable std::mutex interrupt_mutex_;
  bool interruptible_ = false;  // between start() and the end
  std::optional<std::string> interrupt_reason_;
  bool holds_engine_ = false;  // this executor's query is the process's one
  // The call the rules are waiting for.
  std::string pending_name_;
  std::vector<tactical::Value> pending_args_;
  ActionId in_flight_ = 0;  // 0: none
  ActionId next_action_ = 1;
  std::optional<int> answer_;
  std::vector<Phase> phases_;  // the execute_phase/1 calls running, outermost first
  InstanceId next_instance_ = 1;
};

}  // namespace strata::strategic
