#include "strategic/coral_engine.h"

#include <algorithm>
#include <cassert>

#include <fmt/format.h>

#include "petri/dump.h"
#include "strategic/coral_catalogue.h"

namespace strata::strategic {

std::string_view to_string(Outcome outcome) {
  switch (outcome) {
    case Outcome::Completed: return "completed";
    case Outcome::Aborted: return "aborted";
    case Outcome::Failed: return "failed";
  }
  return "failed";
}

namespace {

// A TACTIC's call verb; nullopt for a PHASE.
std::optional<core::CallVerb> verb_of(const coral::ActionSpec& a) {
  if (a.kind == coral::ActionSpec::Kind::Phase) return std::nullopt;
  return a.tactic;
}

// The primitive a TACTIC calls: REPORT goes to the catalogue's `report`.
std::string_view primitive_of(const coral::ActionSpec& a) {
  return a.tactic == coral::ast::TacticType::Report ? std::string_view("report") : std::string_view(a.target);
}

}  // namespace

struct CoralEngine::Instance {
  InstanceId id = 0;
  const coral::CompiledNet* net = nullptr;
  std::size_t net_index = 0;
  std::optional<petri::State> state;  // reset when the instance ends
  std::optional<InstanceId> parent;
  const coral::ActionSpec* caller = nullptr;  // the PHASE action that started it
  std::vector<InstanceId> children;
  std::vector<tactical::Value> params;  // the values of the net's parameters, in order
  std::size_t depth = 0;
  bool dirty = false;
  bool guards_held = false;             // held_: its guards' polls wait for the end of the pass
  std::vector<std::string> trip_terms;  // by guard: the term whose answer marked G.tripped
};

CoralEngine::CoralEngine(const coral::Program& program, Tactics& tactics, EngineOptions options)
    : program_(program), tactics_(tactics), options_(options), self_(std::make_shared<CoralEngine*>(this)) {
  assert(program_.mission.has_value());
  if (options_.seed) rng_.emplace(*options_.seed);
  args_.resize(program_.nets.size());
  params_.resize(program_.nets.size());
  is_exit_.resize(program_.nets.size());
  for (std::size_t n = 0; n < program_.nets.size(); ++n) {
    const coral::CompiledNet& net = program_.nets[n];
    args_[n].resize(net.actions.size());
    params_[n].resize(net.actions.size());
    for (std::size_t t = 0; t < net.actions.size(); ++t) {
      for (const coral::ActionSpec& a : net.actions[t]) {
        std::vector<tactical::Value> values;
        std::vector<std::pair<std::size_t, std::size_t>> slots;
        if (a.kind == coral::ActionSpec::Kind::Tactic && a.tactic == coral::ast::TacticType::Report && a.args.empty()) {
          values.push_back(tactical::Value::of(a.text));
        } else {
          for (const auto& literal : a.args) {
            if (literal.kind == coral::ast::Literal::Kind::Parameter) {
              auto p = std::find_if(net.params.begin(), net.params.end(),
                                    [&](const coral::ast::Param& x) { return x.name.text == literal.text; });
              assert(p != net.params.end() && "the checker guarantees a parameter is declared");
              slots.emplace_back(values.size(), static_cast<std::size_t>(p - net.params.begin()));
            }
            values.push_back(value_of(literal));
          }
        }
        args_[n][t].push_back(std::move(values));
        params_[n][t].push_back(std::move(slots));
      }
    }
    is_exit_[n].assign(net.net.place_count(), false);
    for (petri::PlaceId p : net.exits) is_exit_[n][p] = true;
  }
}

CoralEngine::~CoralEngine() { *self_ = nullptr; }

std::size_t CoralEngine::net_index(const coral::CompiledNet& net) const {
  return static_cast<std::size_t>(&net - program_.nets.data());
}

void CoralEngine::start(std::function<void(const MissionResult&)> on_end) {
  const bool first = begin(std::move(on_end));
  assert(first && "an engine runs one mission");
  if (!first) return;
  draining_ = true;
  firings_this_event_ = 0;
  start_instance(program_.nets[*program_.mission], std::nullopt, nullptr, "");
  run_dirty();
  draining_ = false;
  drain();  // also judges a mission that ended or stalled at once
}

void CoralEngine::cancel(std::string reason) {
  if (running_) fail(std::move(reason));
}

std::vector<tactical::Value> CoralEngine::arguments(const Instance& inst, petri::TransitionId t,
                                                    std::size_t index) const {
  std::vector<tactical::Value> values = args_[inst.net_index][t][index];
  for (const auto& [arg, param] : params_[inst.net_index][t][index]) {
    assert(param < inst.params.size() && "the checker guarantees a PHASE gives every parameter");
    values[arg] = inst.params[param];
  }
  return values;
}

InstanceId CoralEngine::start_instance(const coral::CompiledNet& net, std::optional<InstanceId> parent,
                                       const coral::ActionSpec* caller_action, std::string_view caller,
                                       std::vector<tactical::Value> params) {
  auto inst = std::make_unique<Instance>();
  inst->params = std::move(params);
  inst->id = static_cast<InstanceId>(instances_.size());
  inst->net = &net;
  inst->net_index = net_index(net);
  inst->state.emplace(net.net);
  inst->parent = parent;
  inst->caller = caller_action;
  if (parent) {
    Instance& p = *instances_[*parent];
    inst->depth = p.depth + 1;
    p.children.push_back(inst->id);
  }
  InstanceId id = inst->id;
  instances_.push_back(std::move(inst));
  Instance& i = *instances_[id];
  if (!net.guards.empty()) {
    i.trip_terms.resize(net.guards.size());
    i.guards_held = true;
    held_.push_back(id);
  }
  PhaseStart event{id, parent.value_or(id), net.name, caller, i.depth, &*i.state, now()};
  observers_.phase_started(event);
  i.dirty = true;
  dirty_.push_back(id);
  // An exit marked from the start ends the phase before it fires anything.
  for (std::size_t e = 0; e < net.exits.size(); ++e) {
    if (i.state->tokens(net.exits[e]) > 0) {
      check_exits(id, net.exits[e]);
      break;
    }
  }
  return id;
}

void CoralEngine::deliver(ActionId id, tactical::CallResult outcome) {
  if (!running_) {
    if (ended_) {
      Notice n{fmt::format("reply for action {} after the mission ended, ignored", id), now()};
      observers_.notice(n);
    }
    return;
  }
  buffer_.push_back(Message{id, std::move(outcome)});
  drain();
}

void CoralEngine::drain() {
  if (draining_) return;  // a reply delivered while handling another: queued
  draining_ = true;
  while (running_ && !buffer_.empty()) {
    Message message = std::move(buffer_.front());
    buffer_.pop_front();
    firings_this_event_ = 0;
    handle(message);
    run_dirty();
  }
  draining_ = false;
  if (!running_ || !buffer_.empty()) return;
  // Guards poll for ever: a mission with nothing but their polls in flight
  // cannot move again by itself.
  for (const auto& [id, action] : in_flight_) {
    if (!action.guard) return;
  }
  // Nothing enabled anywhere (run_dirty ran every touched instance to rest)
  // and nothing in flight: the mission can never move again.
  const coral::CompiledNet& mission = program_.nets[*program_.mission];
  if (mission.exits.empty()) {
    finish({Outcome::Completed, "", "", std::nullopt, now()});
    return;
  }
  MissionResult stalled{
      Outcome::Failed, "",
      fmt::format("mission stalled: no transition enabled and no action in flight; marking: {}", marking_text("; ")),
      std::nullopt, now()};
  stalled.stalled = true;
  finish(stalled);
}

void CoralEngine::handle(Message& message) {
  auto it = in_flight_.find(message.id);
  if (it == in_flight_.end()) {
    // A guard's poll forgotten when its net ended or tripped: expected, not news.
    if (orphaned_polls_.erase(message.id) > 0) return;
    bool late = orphaned_.erase(message.id) > 0;
    Notice n{late ? fmt::format("reply for action {} of a phase that has ended, ignored", message.id)
                  : fmt::format("reply for unknown action {}, ignored", message.id),
             now()};
    observers_.notice(n);
    return;
  }
  InFlight action = it->second;
  in_flight_.erase(it);
  const coral::ActionSpec& a = *action.spec;
  std::string_view kind = core::call_verb_name(a.tactic);  // only TACTICs are in flight
  if (!message.outcome) {
    MissionResult result{Outcome::Failed, "",
                         fmt::format("{} {} failed: {}", kind, primitive_of(a), message.outcome.error().message),
                         message.outcome.error().kind, now()};
    finish(result);
    return;
  }
  const tactical::CallOutcome& out = message.outcome.value();
  std::optional<petri::PlaceId> place;
  switch (a.tactic) {
    case coral::ast::TacticType::Ask: place = a.outcomes.at(out.value ? 0 : 1); break;
    case coral::ast::TacticType::Exec:
    case coral::ast::TacticType::Ood:
      if (!out.value) {
        fail(fmt::format("{} {} was not executed: the vehicle answered 0 at {:.1f} s", kind, primitive_of(a),
                         out.sim_time_s));
        return;
      }
      place = a.outcomes.at(0);
      break;
    case coral::ast::TacticType::Report: break;
  }
  Instance& inst = *instances_[action.instance];
  if (const coral::GuardNode node = inst.net->guard_node(action.t);
      node.role == coral::GuardRole::Ask && place == inst.net->guards[node.guard].loop.back()) {
    inst.trip_terms[node.guard] = inst.net->guards[node.guard].terms[node.term];  // G.tripped: this term tripped it
  }
  ActionFinish f{message.id,      action.instance, inst.net->name,
                 primitive_of(a), out.value,       place ? inst.net->net.place_name(*place) : std::string_view(),
                 out.sim_time_s};
  observers_.action_finished(f);
  if (place) mark(action.instance, *place, 1);
}

void CoralEngine::run_dirty() {
  while (true) {
    // Instances touched by the last message, in the order touched; running one
    // may touch others (a phase started, a caller marked by an exit).
    for (std::size_t i = 0; i < dirty_.size() && running_; ++i) {
      InstanceId id = dirty_[i];
      instances_[id]->dirty = false;
      run_instance(id);
    }
    dirty_.clear();
    if (!running_ || held_.empty()) return;
    // The pass is over: the guards of the instances it started poll now.
    std::vector<InstanceId> held = std::move(held_);
    held_.clear();
    for (InstanceId id : held) {
      Instance& inst = *instances_[id];
      inst.guards_held = false;
      if (inst.state && !inst.dirty) {
        inst.dirty = true;
        dirty_.push_back(id);
      }
    }
  }
}

void CoralEngine::run_instance(InstanceId id) {
  Instance& inst = *instances_[id];
  while (running_ && inst.state && !inst.state->enabled().empty()) {
    std::optional<petri::TransitionId> t = choose(inst);
    if (!t) return;  // only its held guard polls are enabled
    if (firings_this_event_ >= options_.max_firings_per_event) {
      fail(
          fmt::format("net '{}' fired {} transitions without waiting for any reply: it cycles "
                      "without acting (marking: {})",
                      inst.net->name, firings_this_event_, petri::dump_marking(inst.net->net, inst.state->marking())));
      return;
    }
    fire(inst, *t);
  }
}

std::optional<petri::TransitionId> CoralEngine::choose(const Instance& inst) {
  const petri::State& state = *inst.state;
  const petri::EnabledSet& enabled = state.enabled();
  petri::TransitionId best = *enabled.first();
  if (inst.guards_held && inst.net->guard_node(best).role == coral::GuardRole::Poll) {
    // The best transition that is not a held poll, by rank (polls rank above every written one).
    std::optional<petri::TransitionId> other;
    for (std::size_t i = 0; i < enabled.size(); ++i) {
      petri::TransitionId t = enabled.at(i);
      if (inst.net->guard_node(t).role == coral::GuardRole::Poll) continue;
      const int pt = state.net().priority(t);
      if (!other || pt > state.net().priority(*other) || (pt == state.net().priority(*other) && t < *other)) other = t;
    }
    if (!other) return std::nullopt;
    best = *other;
  }
  if (!rng_ || enabled.size() == 1) return best;
  int priority = state.net().priority(best);
  std::vector<petri::TransitionId> candidates;
  for (std::size_t i = 0; i < enabled.size(); ++i) {
    petri::TransitionId t = enabled.at(i);
    if (inst.guards_held && inst.net->guard_node(t).role == coral::GuardRole::Poll) continue;
    if (state.net().priority(t) == priority) candidates.push_back(t);
  }
  // Sorted, so the choice depends on the seed and the net, not on the set's layout.
  std::sort(candidates.begin(), candidates.end());
  return candidates[(*rng_)() % candidates.size()];
}

void CoralEngine::fire(Instance& inst, petri::TransitionId t) {
  const petri::Net& net = inst.net->net;
  Firing& event = firing_;  // reused: its vectors keep their capacity
  event.consumed.clear();
  event.produced.clear();
  if (!observers_.empty()) {
    for (const petri::Arc& arc : net.inputs(t)) event.consumed.emplace_back(net.place_name(arc.node), arc.weight);
    for (const petri::Arc& arc : net.outputs(t)) event.produced.emplace_back(net.place_name(arc.node), arc.weight);
  }
  if (const coral::GuardNode node = inst.net->guard_node(t); node.role == coral::GuardRole::Trip) {
    preempt(inst, inst.net->guards[node.guard]);
    if (!running_ || !inst.state) return;
  }
  if (auto r = inst.state->fire(t); !r) {
    fail(fmt::format("net '{}', transition '{}': {}", inst.net->name, net.transition_name(t), r.error().message));
    return;
  }
  ++firings_;
  ++firings_this_event_;
  if (!observers_.empty()) {
    event.instance = inst.id;
    event.net = inst.net->name;
    event.transition = t;
    event.transition_name = net.transition_name(t);
    event.state = &*inst.state;
    event.index = firings_;
    event.sim_time_s = now();
    observers_.fired(event);
  }
  const auto& actions = inst.net->actions[t];
  for (std::size_t i = 0; i < actions.size() && running_ && inst.state; ++i) issue(inst, t, i, actions[i]);
  // Signals into an exit end the phase, after its actions are issued (so a
  // REPORT beside `signal { abort }` is still sent).
  if (!running_ || !inst.state) return;
  for (const petri::Arc& arc : net.outputs(t)) {
    if (is_exit_[inst.net_index][arc.node]) {
      check_exits(inst.id, arc.node);
      return;
    }
  }
}

void CoralEngine::issue(Instance& inst, petri::TransitionId t, std::size_t index, const coral::ActionSpec& a) {
  ActionId id = next_action_++;
  std::string_view transition = inst.net->net.transition_name(t);
  const coral::GuardNode node = inst.net->guard_node(t);
  const bool polls = node.role == coral::GuardRole::Poll || node.role == coral::GuardRole::Ask;
  std::vector<tactical::Value> args = arguments(inst, t, index);
  ActionStart event{id,
                    inst.id,
                    verb_of(a),
                    primitive_of(a),
                    transition,
                    now(),
                    polls ? std::string_view(inst.net->guards[node.guard].name) : std::string_view(),
                    args};
  observers_.action_started(event);
  if (a.kind == coral::ActionSpec::Kind::Phase) {
    const coral::CompiledNet* phase = program_.find(a.target);
    assert(phase && "the checker guarantees PHASE names a phase net");
    if (inst.depth + 1 > options_.max_phase_depth) {
      fail(fmt::format("PHASE({}) in '{}' would nest phases {} deep (limit {}): does a phase run itself?", a.target,
                       inst.net->name, inst.depth + 1, options_.max_phase_depth));
      return;
    }
    start_instance(*phase, inst.id, &a, transition, std::move(args));
    return;
  }
  if (a.tactic == coral::ast::TacticType::Report) {
    // A REPORT marks nothing and waits for nothing: sent, not tracked.
    tactics_.call(primitive_of(a), std::move(args), [](const tactical::CallResult&) {});
    return;
  }
  in_flight_.emplace(id, InFlight{inst.id, &a, transition, t, polls});
  std::weak_ptr<CoralEngine*> self = self_;
  auto deliver = [self, id](tactical::CallResult outcome) {
    if (auto engine = self.lock(); engine && *engine) (*engine)->deliver(id, std::move(outcome));
  };
  if (polls) {
    tactics_.guard_call(event.guard, primitive_of(a), std::move(args), std::move(deliver));
  } else {
    tactics_.call(primitive_of(a), std::move(args), std::move(deliver));
  }
}

void CoralEngine::mark(InstanceId id, petri::PlaceId p, petri::Tokens n) {
  Instance& inst = *instances_[id];
  if (!inst.state) return;
  if (auto r = inst.state->add_tokens(p, n); !r) {
    fail(fmt::format("net '{}': {}", inst.net->name, r.error().message));
    return;
  }
  if (!inst.dirty) {
    inst.dirty = true;
    dirty_.push_back(id);
  }
  if (is_exit_[inst.net_index][p]) check_exits(id, p);
}

void CoralEngine::check_exits(InstanceId id, petri::PlaceId) {
  Instance& inst = *instances_[id];
  // The first exit marked, in declaration order, decides.
  const auto& exits = inst.net->exits;
  for (std::size_t e = 0; e < exits.size(); ++e) {
    if (inst.state->tokens(exits[e]) == 0) continue;
    if (!inst.parent) {
      PhaseEnd end{id, inst.net->name, inst.net->net.place_name(exits[e]), e, false, now()};
      observers_.phase_ended(end);
      MissionResult result{e == 0 ? Outcome::Completed : Outcome::Aborted,
                           std::string(inst.net->net.place_name(exits[e])), "", std::nullopt, now()};
      finish(result);
      return;
    }
    end_instance(id, e, false);
    return;
  }
}

void CoralEngine::end_instance(InstanceId id, std::optional<std::size_t> exit_index, bool cancelled) {
  Instance& inst = *instances_[id];
  if (!inst.state) return;
  for (InstanceId child : inst.children) end_instance(child, std::nullopt, true);
  std::string_view exit = exit_index ? inst.net->net.place_name(inst.net->exits[*exit_index]) : std::string_view();
  PhaseEnd event{id, inst.net->name, exit, exit_index.value_or(0), cancelled, now()};
  observers_.phase_ended(event);
  inst.state.reset();
  for (auto it = in_flight_.begin(); it != in_flight_.end();) {
    if (it->second.instance == id) {
      orphan(it->first, it->second);
      it = in_flight_.erase(it);
    } else {
      ++it;
    }
  }
  if (!cancelled && exit_index && inst.parent && inst.caller) {
    Instance& parent = *instances_[*inst.parent];
    petri::PlaceId place = inst.caller->outcomes.at(*exit_index);
    // The phase's exit marks its caller's place: told like a reply's mark.
    ActionFinish f{
        0, parent.id, parent.net->name, inst.net->name, *exit_index == 0, parent.net->net.place_name(place), now()};
    observers_.action_finished(f);
    mark(*inst.parent, place, 1);
  }
}

void CoralEngine::describe_preempted(const Instance& inst, std::vector<std::string>& phases,
                                     std::vector<std::pair<ActionId, std::string>>& calls) const {
  for (const auto& [id, action] : in_flight_) {
    if (action.instance != inst.id) continue;
    calls.emplace_back(id, fmt::format("{} {}", core::call_verb_name(action.spec->tactic), primitive_of(*action.spec)));
  }
  for (InstanceId child : inst.children) {
    const Instance& c = *instances_[child];
    if (!c.state) continue;
    phases.push_back(fmt::format("{} (instance {})", c.net->name, c.id));
    describe_preempted(c, phases, calls);
  }
}

void CoralEngine::preempt(Instance& inst, const coral::CompiledGuard& guard) {
  GuardTrip trip;
  trip.instance = inst.id;
  trip.net = inst.net->name;
  trip.guard = guard.name;
  trip.condition = inst.trip_terms[static_cast<std::size_t>(&guard - inst.net->guards.data())];
  trip.sim_time_s = now();
  std::vector<std::pair<ActionId, std::string>> calls;
  describe_preempted(inst, trip.preempted_phases, calls);
  std::sort(calls.begin(), calls.end());
  for (auto& [id, text] : calls) trip.preempted_calls.push_back(std::move(text));
  observers_.guard_tripped(trip);
  // The phases it ran end (their calls with them); its own calls are forgotten.
  for (InstanceId child : inst.children) end_instance(child, std::nullopt, true);
  for (auto it = in_flight_.begin(); it != in_flight_.end();) {
    if (it->second.instance == inst.id) {
      orphan(it->first, it->second);
      it = in_flight_.erase(it);
    } else {
      ++it;
    }
  }
}

void CoralEngine::orphan(ActionId id, const InFlight& action) {
  (action.guard ? orphaned_polls_ : orphaned_).insert(id);
}

void CoralEngine::fail(std::string reason) { finish({Outcome::Failed, "", std::move(reason), std::nullopt, now()}); }

void CoralEngine::wind_down(const MissionResult& result) {
  // Phases still running end with the mission.
  if (!instances_.empty()) {
    Instance& mission = *instances_[0];
    for (InstanceId child : mission.children) end_instance(child, std::nullopt, true);
    if (mission.state && result.outcome == Outcome::Failed) {
      // Ended without an exit: say so, so every phase_start has its phase_end.
      PhaseEnd end{0, mission.net->name, "", 0, true, result.sim_time_s};
      observers_.phase_ended(end);
    }
    mission.state.reset();
  }
  for (const auto& [id, action] : in_flight_) orphan(id, action);
  in_flight_.clear();
  buffer_.clear();
}

std::optional<CoralEngine::InstanceView> CoralEngine::instance(InstanceId id) const {
  if (id >= instances_.size()) return std::nullopt;
  const Instance& i = *instances_[id];
  return InstanceView{i.id, i.net, i.state ? &*i.state : nullptr};
}

std::vector<CoralEngine::InstanceView> CoralEngine::live_instances() const {
  std::vector<InstanceView> out;
  for (const auto& i : instances_) {
    if (i->state) out.push_back({i->id, i->net, &*i->state});
  }
  return out;
}

std::string CoralEngine::marking_text(std::string_view separator) const {
  std::string out;
  for (const auto& i : instances_) {
    if (!i->state) continue;
    if (!out.empty()) out += separator;
    out += fmt::format("{}: {}", i->net->name, petri::dump_marking(i->net->net, i->state->marking()));
  }
  return out;
}

}  // namespace strata::strategic
