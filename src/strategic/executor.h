#pragma once
// The Strategic level as the rest of Strata sees it: an executor that runs
// one mission through the Tactics interface and tells observers what it did.
// The CORAL Engine implements it; the PROLOG executor too. The console,
// the mission log and the studio are observers: the executor knows none of
// them, and an observer must not call back into the executor.
//
// Threads: one, the event loop's, for everything but Executor::interrupt().
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/call_verb.h"
#include "core/result.h"
#include "petri/net.h"
#include "tactical/call_error.h"
#include "tactical/value.h"

namespace strata::petri {
class State;
}

namespace strata::strategic {

// How a mission ended.
//  Completed: the mission's first exit was marked (PROLOG: the rules finished).
//  Aborted:   a later exit was marked: the mission's own abort path ran.
//  Failed:    the Strategic level could not go on (a primitive call failed,
//             the link was lost, the net stalled or looped without acting,
//             the run was cancelled); `reason` says which.
enum class Outcome { Completed, Aborted, Failed };
std::string_view to_string(Outcome outcome);

struct MissionResult {
  Outcome outcome = Outcome::Failed;
  std::string exit;    // CORAL: the exit place of the mission net that ended it
  std::string reason;  // Failed (and Aborted when known): why, for people
  // Failed because a primitive call failed: how it failed (TimedOut or
  // LinkLost mean the link to the vehicle is gone).
  std::optional<tactical::CallError::Kind> call_error;
  double sim_time_s = 0.0;
  // Failed because the mission could never move again (CORAL: no transition
  // enabled anywhere and no action in flight).
  bool stalled = false;
};

// A net (or a PROLOG phase) being run: the mission itself is instance 0,
// each PHASE action starts a new instance whose parent is the caller's.
using InstanceId = std::uint32_t;
using ActionId = std::uint64_t;

struct PhaseStart {
  InstanceId instance = 0;
  InstanceId parent = 0;                // the mission itself: its own id (0)
  std::string_view name;                // the net's (phase's) name
  std::string_view caller;              // the transition whose PHASE action started it; "" for the mission
  std::size_t depth = 0;                // 0 for the mission, 1 for a phase it runs, ...
  const petri::State* state = nullptr;  // CORAL: the initial marking; PROLOG: null
  double sim_time_s = 0.0;
};

struct PhaseEnd {
  InstanceId instance = 0;
  std::string_view name;
  std::string_view exit;       // the exit place that ended it ("" if cancelled)
  std::size_t exit_index = 0;  // 0: the first exit (completed)
  bool cancelled = false;      // ended because its caller ended first
  double sim_time_s = 0.0;
};

// One firing: steps 4-5 of the engine. consumed/produced are the token
// changes of the firing itself (wait and signal arcs); marks carried later
// by replies come as ActionFinish.
struct Firing {
  InstanceId instance = 0;
  std::string_view net;
  petri::TransitionId transition = 0;
  std::string_view transition_name;
  std::vector<std::pair<std::string_view, petri::Tokens>> consumed;
  std::vector<std::pair<std::string_view, petri::Tokens>> produced;
  const petri::State* state = nullptr;  // the marking after the firing
  std::uint64_t index = 0;              // 1 for the run's first firing
  double sim_time_s = 0.0;
};

// A primitive call (verb set) or a PHASE (verb nullopt) being issued.
struct ActionStart {
  ActionId id = 0;
  InstanceId instance = 0;
  std::optional<core::CallVerb> verb;  // the call's verb; nullopt: a PHASE
  std::string_view primitive;          // the primitive, or the phase net
  std::string_view transition;         // CORAL: the transition that issued it
  double sim_time_s = 0.0;
  // A guard's own poll (its `sleep` or a term of its condition): the name
  // of the guard; "" for a call of the mission itself.
  std::string_view guard = {};
  // The call's (or the phase's) arguments, valid during the callback.
  std::span<const tactical::Value> args = {};

  bool is_phase() const { return !verb.has_value(); }
  bool is_call(core::CallVerb v) const { return verb == v; }
  // "exec", "ask", "ood", "report" (core::call_verb_name) or "phase".
  std::string_view kind_name() const { return verb ? core::call_verb_name(*verb) : std::string_view("phase"); }
};

// A reply marked a place; or (id 0, primitive = the phase's name) a phase's
// exit marked its caller's place.
struct ActionFinish {
  ActionId id = 0;
  InstanceId instance = 0;
  std::string_view net;
  std::string_view primitive;
  bool value = false;      // the answer (1/0)
  std::string_view marks;  // the place the reply marked, "" if none
  double sim_time_s = 0.0;
};

// A guard tripped (docs/language.md, "guard"): a term of its condition was
// found true when polled. The phases and calls of its net that were running
// are pre-empted before its handler starts: the phases end (cancelled), and
// the replies of the calls still in flight will be ignored.
struct GuardTrip {
  InstanceId instance = 0;  // the net (mission or phase) that declares the guard
  std::string_view net;
  std::string_view guard = {};
  std::string_view condition;                 // the term found true: "system_problem", "not gps_available"
  std::vector<std::string> preempted_phases;  // "leg (instance 3)", outermost first
  std::vector<std::string> preempted_calls;   // "exec sleep", in the order issued
  double sim_time_s = 0.0;
};

// Something worth a line in the log that is not a firing: a reply for an
// unknown or finished action, an internal limit reached.
struct Notice {
  std::string text;
  double sim_time_s = 0.0;
};

class Observer {
 public:
  virtual ~Observer() = default;
  virtual void phase_started(const PhaseStart&) {}
  virtual void phase_ended(const PhaseEnd&) {}
  virtual void fired(const Firing&) {}
  virtual void action_started(const ActionStart&) {}
  virtual void action_finished(const ActionFinish&) {}
  virtual void notice(const Notice&) {}
  virtual void guard_tripped(const GuardTrip&) {}
  virtual void mission_ended(const MissionResult&) {}
};

class Executor {
 public:
  virtual ~Executor() = default;
  // Observers are told in the order added; each must outlive the run.
  virtual void add_observer(Observer& observer) = 0;
  // Starts the mission. on_end is called exactly once, from the event loop,
  // after observers heard mission_ended; nothing is issued after it.
  virtual void start(std::function<void(const MissionResult&)> on_end) = 0;
  // Ends a running mission now (the operator's interrupt): Outcome::Failed
  // with reason. Replies still in flight are ignored when they come.
  virtual void cancel(std::string reason) = 0;
  // The operator's interrupt, from outside the event loop: hands the loop
  // back soon (well under 100 ms) so that a cancel(reason) the caller posts
  // to the loop can run. Thread-safe: meant for a thread other than the
  // loop's (one that sigwait()s for SIGINT, an HTTP worker); never blocks;
  // not async-signal-safe (call it from a thread, not a signal handler).
  // An executor that never holds the loop (the CORAL Engine) has nothing to
  // do. One whose work can hold it (PROLOG rules computing, or in sleep/1)
  // stops that work and ends the mission itself, Outcome::Failed with
  // reason, from the loop; the posted cancel then finds it ended. Ignored
  // when the executor is not running. The caller keeps the executor alive
  // across the call (run::RunSession holds its lock around it).
  virtual void interrupt(const std::string& /*reason*/) {}
  virtual bool running() const = 0;
};

// The observers of one executor, told in the order added: one call per kind
// of event, so that an executor says what happened in one line.
class ObserverList {
 public:
  void add(Observer& observer) { observers_.push_back(&observer); }
  bool empty() const { return observers_.empty(); }

  void phase_started(const PhaseStart& e) const {
    for (Observer* o : observers_) o->phase_started(e);
  }
  void phase_ended(const PhaseEnd& e) const {
    for (Observer* o : observers_) o->phase_ended(e);
  }
  void fired(const Firing& e) const {
    for (Observer* o : observers_) o->fired(e);
  }
  void action_started(const ActionStart& e) const {
    for (Observer* o : observers_) o->action_started(e);
  }
  void action_finished(const ActionFinish& e) const {
    for (Observer* o : observers_) o->action_finished(e);
  }
  void notice(const Notice& e) const {
    for (Observer* o : observers_) o->notice(e);
  }
  void guard_tripped(const GuardTrip& e) const {
    for (Observer* o : observers_) o->guard_tripped(e);
  }
  void mission_ended(const MissionResult& result) const {
    for (Observer* o : observers_) o->mission_ended(result);
  }

 private:
  std::vector<Observer*> observers_;
};

// What both executors share: their observers, whether the mission runs,
// and the one end of a run. An executor calls begin() as its start()
// begins, and finish() for every way its mission ends.
class ExecutorBase : public Executor {
 public:
  void add_observer(Observer& observer) final { observers_.add(observer); }
  bool running() const final { return running_; }

 protected:
  // Keeps on_end and marks the mission running. False, and nothing
  // changed, when the executor runs or has run: one mission per executor.
  [[nodiscard]] bool begin(std::function<void(const MissionResult&)> on_end);
  // The end of the run, once: nothing when not running. Otherwise, in this
  // order: running_ false and ended_ true; wind_down(result), the
  // executor's own end (phases still running end, calls in flight are
  // forgotten); observers hear mission_ended(result); on_end is called,
  // and dropped. Nothing is issued after it.
  void finish(const MissionResult& result);
  // The executor's part of finish(): told the phases' ends it owes.
  virtual void wind_down(const MissionResult& result) = 0;

  ObserverList observers_;
  // Set by begin() and finish() alone; the executors read them.
  bool running_ = false;  // between begin() and finish()
  bool ended_ = false;    // finish() has run

 private:
  std::function<void(const MissionResult&)> on_end_;
};

}  // namespace strata::strategic
