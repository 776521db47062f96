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
//  - a guard (guard/4, phase_guard/5; docs/prolog.md §8) trips: its scope
//    (mission/0, or the phase) is unwound and its handler runs in its
//    place; the mission then ends as the rules do.
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
#include <map>
#include <memory>
#include <mutex>
#include <set>
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
  // A guard of a scope, polling: its sleep, then its terms in turn.
  struct GuardPoll {
    GuardSpec spec;
    ActionId in_flight = 0;  // its sleep or ask; 0 when stopped
    std::size_t term = 0;    // the term asked; spec.terms.size() while it sleeps
  };
  // A guarded scope: mission/0 or an execute_phase/1 call, with its guards.
  struct Scope {
    std::uint64_t id = 0;
    InstanceId instance = 0;
    std::string net;
    std::size_t depth = 0;  // phases_.size() when it opened: the phases inside it come after
    std::vector<GuardPoll> guards;
    bool polling = false;                // its guards' first sleeps are issued
    std::optional<std::string> tripped;  // the guard that tripped it: its handler is due
  };
  // A guard's poll in flight.
  struct GuardCall {
    std::uint64_t scope = 0;
    std::size_t guard = 0;
    std::string text;  // "exec sleep", "ask system_problem"
  };

  // PrologHost
  void primitive(const std::string& name, std::vector<tactical::Value> args) override;
  std::optional<int> answer() override { return answer_; }
  void report(const std::string& name, std::vector<tactical::Value> args) override;
  void phase_started(const std::string& phase) override;
  void phase_ended(const std::string& phase, const std::string& exit) override;
  std::uint64_t open_guards(const std::vector<GuardSpec>& guards) override;
  std::optional<std::string> close_guards(std::uint64_t scope) override;
  std::optional<GuardTripSignal> pending_trip() const override;
  void call_not_made(const std::string& name) override;

  // Guards: the first sleeps of the scopes opened since the last call, after
  // the rules' call; a guard's next poll; a reply to one; a trip.
  void start_guards();
  void poll(Scope& scope, std::size_t guard);
  void guard_reply(const GuardCall& call, ActionId id, tactical::CallResult outcome);
  void trip(std::size_t scope, std::size_t guard);
  // Stops the guards of scopes_[from...]: their polls in flight are forgotten.
  void stop_guards(std::size_t from);
  Scope* find_scope(std::uint64_t id);

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
  std::vector<Scope> scopes_;                  // the guarded scopes open, outermost first
  std::map<ActionId, GuardCall> guard_calls_;  // guard polls in flight
  std::set<ActionId> forgotten_;               // calls a trip or the end pre-empted: replies ignored
  std::uint64_t next_scope_ = 1;
  std::optional<std::string> mission_handler_;  // the guard of mission/0 whose handler replaced it
};

}  // namespace strata::strategic
