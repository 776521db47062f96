#pragma once
// The CORAL Engine (paper §3.2, docs/architecture.md): runs a compiled mission
// library as Petri nets, event-driven on one thread with no polling loop.
//
// For each message in the input buffer: (1) add the marks it carries;
// (2) find the enabled transitions; (3) choose one: highest priority, then
// declaration order, or a seeded random choice among the best priority;
// (4) remove its input tokens; (5) issue its actions and add its signal
// marks; (6) repeat 2-5 until nothing is enabled. A TACTIC action is a
// primitive call with its own id; its reply is a later message that marks
// the action's outcome place. Several actions may be in flight at once.
//
// The mission library: a PHASE(name, p_1..p_k) action starts a new instance
// of phase net `name` at its initial marking. When its i-th exit is marked
// the instance ends (with every phase it started, and its replies still in
// flight are ignored) and p_i is marked in the calling instance. A phase net
// with parameters (`net leg(x0, y0)`) runs with the values its PHASE call
// gives (`PHASE(leg(0, 100), ...)`): the engine substitutes them into the
// instance's primitive calls and nested PHASE calls when they are issued, so
// the EXEC a leg sends carries the numbers of that call. The mission
// ends when an exit of the mission net is marked: the first exit completes
// it, a later one aborts it. A mission net with no exits completes when
// nothing is enabled and nothing is in flight.
//
// Failures end the mission with Outcome::Failed: a primitive call that
// fails (error, lost link, timeout), an EXEC or OOD the vehicle answered 0
// ("did not execute": CORAL has no place for that outcome), a token count
// overflow, a stall (an exit never marked, nothing enabled, nothing in
// flight), or more than max_firings_per_event firings without a reply (a net
// that cycles without acting).
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "coral/program.h"
#include "petri/state.h"
#include "strategic/executor.h"
#include "strategic/tactics.h"

namespace strata::strategic {

struct EngineOptions {
  // Unset: priority, then declaration order. Set: a random choice among the
  // enabled transitions of the best priority, from this seed.
  std::optional<std::uint64_t> seed;
  // Firings allowed while handling one message before the net is judged to
  // be cycling without acting.
  std::uint64_t max_firings_per_event = 100'000;
  // How deep PHASE may nest (a phase that runs itself would recurse forever);
  // the verifier checks the same limit (coral::kMaxPhaseDepth).
  std::size_t max_phase_depth = coral::kMaxPhaseDepth;
};

class CoralEngine final : public ExecutorBase {
 public:
  // program must hold a mission net; program and tactics must outlive the engine.
  CoralEngine(const coral::Program& program, Tactics& tactics, EngineOptions options = {});
  ~CoralEngine() override;

  // on_end may be called inside start() if the mission ends without issuing
  // a single action.
  void start(std::function<void(const MissionResult&)> on_end) override;
  void cancel(std::string reason) override;

  // The input buffer: the reply to action id. Tactics replies come here; a
  // reply for an id the engine never issued, or for an action whose phase
  // has ended, is told to observers as a Notice and otherwise ignored.
  void deliver(ActionId id, tactical::CallResult outcome);

  // Inspection, for observers and tests.
  struct InstanceView {
    InstanceId id;
    const coral::CompiledNet* net;
    const petri::State* state;  // null once the instance has ended
  };
  std::optional<InstanceView> instance(InstanceId id) const;
  // Live instances, mission first, then phases in the order started.
  std::vector<InstanceView> live_instances() const;
  // "net: place:1 other:2" for each live instance, joined by separator.
  std::string marking_text(std::string_view separator = "\n") const;
  std::size_t in_flight() const { return in_flight_.size(); }
  std::uint64_t firings() const { return firings_; }

 private:
  struct Instance;
  struct InFlight {
    InstanceId instance;
    const coral::ActionSpec* spec;
    std::string_view transition;
    petri::TransitionId t = 0;
    bool guard = false;  // a guard's own poll: not progress of the mission
  };
  struct Message {
    ActionId id;
    tactical::CallResult outcome;
  };
  // Arguments of each action, converted once: [net][transition][action].
  // An argument naming a parameter holds a placeholder there, and its
  // (argument index, parameter index) is in the ParamTable.
  using ArgTable = std::vector<std::vector<std::vector<std::vector<tactical::Value>>>>;
  using ParamTable = std::vector<std::vector<std::vector<std::vector<std::pair<std::size_t, std::size_t>>>>>;

  void drain();
  void handle(Message& message);
  void run_dirty();
  void run_instance(InstanceId id);
  // The transition to fire next; nullopt when only held guard polls are enabled.
  std::optional<petri::TransitionId> choose(const Instance& inst);
  // A guard trips (its G.trip fires): tell observers, end the net's phases,
  // forget its calls in flight.
  void preempt(Instance& inst, const coral::CompiledGuard& guard);
  void describe_preempted(const Instance& inst, std::vector<std::string>& phases,
                          std::vector<std::pair<ActionId, std::string>>& calls) const;
  void fire(Instance& inst, petri::TransitionId t);
  void issue(Instance& inst, petri::TransitionId t, std::size_t index, const coral::ActionSpec& a);
  InstanceId start_instance(const coral::CompiledNet& net, std::optional<InstanceId> parent,
                            const coral::ActionSpec* caller_action, std::string_view caller,
                            std::vector<tactical::Value> params = {});
  // The arguments of action `index` of transition t as inst issues them: its
  // parameters replaced by inst's values.
  std::vector<tactical::Value> arguments(const Instance& inst, petri::TransitionId t, std::size_t index) const;
  // Adds n tokens to p in inst; ends the instance if p is an exit.
  void mark(InstanceId id, petri::PlaceId p, petri::Tokens n);
  void check_exits(InstanceId id, petri::PlaceId p);
  void end_instance(InstanceId id, std::optional<std::size_t> exit_index, bool cancelled);
  // Forgets a call in flight: its reply, when it comes, is ignored.
  void orphan(ActionId id, const InFlight& action);
  void fail(std::string reason);
  // finish()'s part: the phases still running end, replies still to come are ignored.
  void wind_down(const MissionResult& result) override;
  std::size_t net_index(const coral::CompiledNet& net) const;
  double now() const { return tactics_.sim_time_s(); }

  const coral::Program& program_;
  Tactics& tactics_;
  EngineOptions options_;
  ArgTable args_;
  ParamTable params_;
  std::vector<std::vector<bool>> is_exit_;  // [net][place]
  std::vector<std::unique_ptr<Instance>> instances_;
  std::unordered_map<ActionId, InFlight> in_flight_;
  std::unordered_set<ActionId> orphaned_;        // issued by an instance that has ended
  std::unordered_set<ActionId> orphaned_polls_;  // the same, a guard's polls: ignored without a notice
  std::deque<Message> buffer_;
  std::vector<InstanceId> dirty_;
  // Instances started in this pass whose guards poll once the pass is over:
  // a scope's own first calls go out before its guards' first sleeps.
  std::vector<InstanceId> held_;
  std::optional<std::mt19937_64> rng_;
  Firing firing_;  // scratch for the event told to observers
  ActionId next_action_ = 1;
  std::uint64_t firings_ = 0;
  std::uint64_t firings_this_event_ = 0;
  bool draining_ = false;
  // Keeps callbacks from the Tactics level harmless after the engine is gone.
  std::shared_ptr<CoralEngine*> self_;
};

}  // namespace strata::strategic
