#include "strategic/prolog_executor.h"

#include <algorithm>
#include <cassert>

#include <fmt/format.h>

#include "core/text.h"

namespace strata::strategic {
namespace {

// A PrologExecutor between start() and its end holds the Prolog engine.
bool g_running = false;

constexpr std::size_t kMaxExceptionText = 400;

std::string shortened(std::string text) { return core::shorten(std::move(text), kMaxExceptionText, " ..."); }

bool completes(const std::string& exit) { return exit == "complete" || exit == "done"; }

}  // namespace

PrologExecutor::PrologExecutor(PrologMission& mission, Tactics& tactics, const tactical::Catalogue& catalogue,
                               PrologOptions options)
    : mission_(mission),
      tactics_(tactics),
      catalogue_(catalogue),
      options_(options),
      self_(std::make_shared<PrologExecutor*>(this)) {}

PrologExecutor::~PrologExecutor() {
  *self_ = nullptr;
  query_.reset();
  if (holds_engine_) g_running = false;
}

void PrologExecutor::start(std::function<void(const MissionResult&)> on_end) {
  if (!begin(std::move(on_end))) return;
  PhaseStart event{0, 0, mission_.name(), "", 0, nullptr, now()};
  observers_.phase_started(event);
  // SWI-Prolog runs one suspended query at a time here; and a mission's
  // rules keep the facts they asserted, so they run once per load.
  if (g_running) {
    fail("another PROLOG mission is running in this process: one at a time");
    return;
  }
  if (mission_.started()) {
    fail("these rules have run already: load the mission again for another run");
    return;
  }
  g_running = true;
  holds_engine_ = true;
  {
    std::lock_guard lock(interrupt_mutex_);
    interruptible_ = true;
  }
  query_ = std::make_unique<PrologMissionQuery>(mission_, static_cast<PrologHost&>(*this), options_.inference_limit);
  resume();
}

void PrologExecutor::cancel(std::string reason) {
  if (running_) fail(std::move(reason));
}

void PrologExecutor::interrupt(const std::string& reason) {
  {
    std::lock_guard lock(interrupt_mutex_);
    if (!interruptible_) return;
    if (!interrupt_reason_) interrupt_reason_ = reason;
  }
  // Outside the lock: the loop's thread takes it to end the mission, and
  // raising never waits for the query anyway. False when the rules do not
  // run (they wait for the vehicle, or the mission has just ended).
  interrupt_rules(static_cast<const PrologHost&>(*this));
}

std::optional<std::string> PrologExecutor::interrupt_reason() const {
  std::lock_guard lock(interrupt_mutex_);
  return interrupt_reason_;
}

void PrologExecutor::resume() {
  using Status = prolog::Query::Status;
  Status status = query_->next();
  answer_.reset();
  // Whatever the rules did meanwhile (stopped by the interrupt, or yielded
  // or ended just before it reached them), the operator asked to stop.
  if (auto why = interrupt_reason()) {
    fail(std::move(*why));
    return;
  }
  switch (status) {
    case Status::Yield: issue(); return;
    case Status::True:
    case Status::Last: rules_ended(); return;
    case Status::False:
      fail(mission_handler_ ? fmt::format("the handler of guard {} failed", *mission_handler_)
                            : std::string("mission/0 failed: none of its rules succeeded"));
      return;
    case Status::Exception: break;
  }
  if (auto code = query_->halted()) {
    // An abort whenever it comes: the rules gave up, and the vehicle is
    // wherever they left it (the run's end path surfaces it).
    finish({Outcome::Aborted, "mission_abort",
            query_->exception_text() == "strata_halt" ? std::string("the rules called halt")
                                                      : fmt::format("the rules called halt({})", *code),
            std::nullopt, now()});
  } else if (query_->interrupted()) {
    fail("the rules were interrupted");  // not reached: interrupt() set a reason first
  } else if (query_->inference_limit_exceeded()) {
    fail(
        fmt::format("the rules made {} inferences without calling a primitive: an endless loop? "
                    "(the limit is --inference-limit)",
                    options_.inference_limit));
  } else if (query_->out_of_stack()) {
    // error(resource_error(R), _): SWI's stack (global, local, trail: one
    // limit), the C stack (a term nested too deep), or memory.
    const std::string& e = query_->exception_text();
    const char* what = e.find("c_stack") != std::string::npos  ? "C stack"
                       : e.find("memory") != std::string::npos ? "memory"
                                                               : "Prolog stack";
    fail(fmt::format("the rules ran out of {}: endless recursion, or a term too large or nested too deep?", what));
  } else if (query_->cannot_suspend()) {
    fail(
        "the rules called a primitive where Prolog cannot wait for the vehicle (inside a cleanup "
        "handler, with_output_to/2 or format/2's ~@): " +
        shortened(query_->exception_text()));
  } else {
    fail("the rules raised an exception: " + shortened(query_->exception_text()));
  }
}

void PrologExecutor::primitive(const std::string& name, std::vector<tactical::Value> args) {
  pending_name_ = name;
  pending_args_ = std::move(args);
}

void PrologExecutor::issue() {
  const tactical::Primitive* p = catalogue_.find(pending_name_);
  ActionId id = next_action_++;
  in_flight_ = id;
  ActionStart event{id, current_instance(), p ? p->kind : core::CallVerb::Exec, pending_name_, "", now(),
                    {}, pending_args_};
  observers_.action_started(event);
  std::weak_ptr<PrologExecutor*> self = self_;
  tactics_.call(pending_name_, std::move(pending_args_), [self, id](tactical::CallResult outcome) {
    if (auto executor = self.lock(); executor && *executor) (*executor)->deliver(id, std::move(outcome));
  });
  start_guards();
}

void PrologExecutor::deliver(ActionId id, tactical::CallResult outcome) {
  if (forgotten_.erase(id) > 0) return;  // pre-empted by a trip, or by the end: nobody waits
  if (auto it = guard_calls_.find(id); it != guard_calls_.end()) {
    GuardCall call = std::move(it->second);
    guard_calls_.erase(it);
    guard_reply(call, id, std::move(outcome));
    return;
  }
  if (!running_ || id != in_flight_) {
    Notice n{fmt::format("a reply for call {}, which the mission no longer waits for, was ignored", id), now()};
    observers_.notice(n);
    return;
  }
  in_flight_ = 0;
  // Interrupted while the rules waited: the reply is ignored, as after cancel().
  if (auto why = interrupt_reason()) {
    fail(std::move(*why));
    return;
  }
  const tactical::Primitive* p = catalogue_.find(pending_name_);
  std::string_view kind = core::call_verb_name(p ? p->kind : core::CallVerb::Exec);
  if (!outcome) {
    fail(fmt::format("{} {} failed: {}", kind, pending_name_, outcome.error().message), outcome.error().kind);
    return;
  }
  const tactical::CallOutcome& out = outcome.value();
  std::string net = phases_.empty() ? mission_.name() : phases_.back().name;
  ActionFinish f{id, current_instance(), net, pending_name_, out.value, "", out.sim_time_s};
  observers_.action_finished(f);
  if (!out.value && p && (p->kind == tactical::Kind::Exec || p->kind == tactical::Kind::Ood)) {
    // As in CORAL: a command the vehicle did not carry out ends the mission.
    fail(
        fmt::format("{} {} was not executed: the vehicle answered 0 at {:.1f} s", kind, pending_name_, out.sim_time_s));
    return;
  }
  answer_ = out.value ? 1 : 0;
  resume();
}

void PrologExecutor::report(const std::string& name, std::vector<tactical::Value> args) {
  ActionStart event{next_action_++, current_instance(), core::CallVerb::Report, name, "", now(), {}, args};
  observers_.action_started(event);
  tactics_.call(name, std::move(args), [](const tactical::CallResult&) {});
}

void PrologExecutor::phase_started(const std::string& phase) {
  // Rules that caught a trip and went on: their phases run nowhere, as their calls.
  if (pending_trip()) return;
  InstanceId parent = current_instance();
  phases_.push_back({next_instance_++, phase});
  PhaseStart event{phases_.back().instance, parent, phases_.back().name, "", phases_.size(), nullptr, now()};
  observers_.phase_started(event);
}

void PrologExecutor::phase_ended(const std::string& phase, const std::string& exit) {
  if (pending_trip()) return;  // the trip ended the phases it pre-empted
  if (phases_.empty() || phases_.back().name != phase) {
    Notice n{fmt::format("phase {} ended again: the rules backtracked into it (is a cut missing after "
                         "execute_phase/1?)",
                         phase),
             now()};
    observers_.notice(n);
    return;
  }
  PhaseEnd event{phases_.back().instance, phases_.back().name, exit, completes(exit) ? 0u : 1u, false, now()};
  observers_.phase_ended(event);
  phases_.pop_back();
}

void PrologExecutor::rules_ended() {
  query_->close();
  auto rules = mission_outcome(mission_);
  if (!rules) {
    fail("cannot tell how the rules ended: " + shortened(rules.error().message));
    return;
  }
  if (rules.value() == strategic::RulesOutcome::Aborted) {
    finish(
        {Outcome::Aborted, "mission_abort", "the rules ended with current_phase(mission_abort)", std::nullopt, now()});
  } else {
    finish({Outcome::Completed, "", "", std::nullopt, now()});
  }
}

void PrologExecutor::fail(std::string reason, std::optional<tactical::CallError::Kind> call_error) {
  finish({Outcome::Failed, "", std::move(reason), call_error, now()});
}

void PrologExecutor::wind_down(const MissionResult& result) {
  {
    std::lock_guard lock(interrupt_mutex_);
    interruptible_ = false;
  }
  if (query_) query_->close();
  if (holds_engine_) {
    g_running = false;
    holds_engine_ = false;
  }
  in_flight_ = 0;  // its reply, if it comes, is a notice
  stop_guards(0);  // theirs are not: nobody waited for a guard's poll
  scopes_.clear();
  // Phases still running end with the mission, innermost first.
  while (!phases_.empty()) {
    PhaseEnd end{phases_.back().instance, phases_.back().name, "", 0, true, result.sim_time_s};
    observers_.phase_ended(end);
    phases_.pop_back();
  }
  PhaseEnd mission{0,
                   mission_.name(),
                   result.exit,
                   result.outcome == Outcome::Completed ? 0u : 1u,
                   result.outcome == Outcome::Failed,
                   result.sim_time_s};
  observers_.phase_ended(mission);
}

// Guards (docs/prolog.md §8). A scope's guards start polling right after
// the first call the rules make in it, as a CORAL scope's sleeps follow its
// first firings; each guard sleeps its period, asks its terms in order, and
// trips on the first that holds, or sleeps again.

std::uint64_t PrologExecutor::open_guards(const std::vector<GuardSpec>& guards) {
  Scope scope;
  scope.id = next_scope_++;
  scope.instance = current_instance();
  scope.net = phases_.empty() ? mission_.name() : phases_.back().name;
  scope.depth = phases_.size();
  for (const GuardSpec& g : guards) scope.guards.push_back({g, 0, g.terms.size()});
  scopes_.push_back(std::move(scope));
  return scopes_.back().id;
}

std::optional<std::string> PrologExecutor::close_guards(std::uint64_t id) {
  auto it = std::find_if(scopes_.begin(), scopes_.end(), [id](const Scope& s) { return s.id == id; });
  if (it == scopes_.end()) return std::nullopt;
  std::optional<std::string> tripped = it->tripped;
  if (tripped && it->instance == 0 && it->depth == 0) mission_handler_ = tripped;
  // Scopes inside it that the rules left without closing (an exception
  // past their clean-up) close with it.
  const auto from = static_cast<std::size_t>(it - scopes_.begin());
  stop_guards(from);
  scopes_.erase(scopes_.begin() + static_cast<std::ptrdiff_t>(from), scopes_.end());
  return tripped;
}

std::optional<GuardTripSignal> PrologExecutor::pending_trip() const {
  for (const Scope& s : scopes_) {
    if (s.tripped) return GuardTripSignal{s.id, *s.tripped};
  }
  return std::nullopt;
}

void PrologExecutor::call_not_made(const std::string& name) {
  const tactical::Primitive* p = catalogue_.find(name);
  auto trip = pending_trip();
  Notice n{fmt::format("{} {} was not called: guard {} has tripped, and nothing reaches the vehicle before its "
                       "handler runs (a call in a cleanup handler, or after a catch of the trip)",
                       core::call_verb_name(p ? p->kind : core::CallVerb::Exec), name, trip ? trip->guard : "?"),
           now()};
  observers_.notice(n);
}

PrologExecutor::Scope* PrologExecutor::find_scope(std::uint64_t id) {
  auto it = std::find_if(scopes_.begin(), scopes_.end(), [id](const Scope& s) { return s.id == id; });
  return it == scopes_.end() ? nullptr : &*it;
}

void PrologExecutor::start_guards() {
  // Outer scopes first; within one, in declaration order.
  for (Scope& scope : scopes_) {
    if (scope.polling || scope.tripped) continue;
    scope.polling = true;
    for (std::size_t g = 0; g < scope.guards.size(); ++g) poll(scope, g);
  }
}

void PrologExecutor::poll(Scope& scope, std::size_t guard) {
  GuardPoll& g = scope.guards[guard];
  const bool sleeping = g.term == g.spec.terms.size();
  std::string name = sleeping ? std::string("sleep") : g.spec.terms[g.term].ask;
  std::vector<tactical::Value> args =
      sleeping ? std::vector<tactical::Value>{tactical::Value::of(g.spec.period_s)} : g.spec.terms[g.term].args;
  const core::CallVerb verb = sleeping ? core::CallVerb::Exec : core::CallVerb::Ask;
  ActionId id = next_action_++;
  g.in_flight = id;
  guard_calls_[id] = {scope.id, guard, fmt::format("{} {}", core::call_verb_name(verb), name)};
  ActionStart event{id, scope.instance, verb, name, "", now(), g.spec.name, args};
  observers_.action_started(event);
  std::weak_ptr<PrologExecutor*> self = self_;
  tactics_.guard_call(g.spec.name, name, std::move(args), [self, id](tactical::CallResult outcome) {
    if (auto executor = self.lock(); executor && *executor) (*executor)->deliver(id, std::move(outcome));
  });
}

void PrologExecutor::guard_reply(const GuardCall& call, ActionId id, tactical::CallResult outcome) {
  if (!running_) return;
  if (auto why = interrupt_reason()) {
    fail(std::move(*why));
    return;
  }
  Scope* scope = find_scope(call.scope);
  assert(scope && "a guard's poll in flight belongs to a scope still open");
  GuardPoll& g = scope->guards[call.guard];
  g.in_flight = 0;
  const bool slept = g.term == g.spec.terms.size();
  const std::string name = slept ? std::string("sleep") : g.spec.terms[g.term].ask;
  if (!outcome) {
    // As a call of the rules fails, and as CORAL says it.
    fail(fmt::format("{} failed: {}", call.text, outcome.error().message), outcome.error().kind);
    return;
  }
  const tactical::CallOutcome& out = outcome.value();
  ActionFinish f{id, scope->instance, scope->net, name, out.value, "", out.sim_time_s};
  observers_.action_finished(f);
  if (slept) {
    if (!out.value) {
      fail(fmt::format("exec sleep was not executed: the vehicle answered 0 at {:.1f} s", out.sim_time_s));
      return;
    }
    g.term = 0;
  } else if (out.value != g.spec.terms[g.term].negated) {
    trip(static_cast<std::size_t>(scope - scopes_.data()), call.guard);
    return;
  } else {
    ++g.term;  // past the last term: sleep again
  }
  poll(*scope, call.guard);
}

void PrologExecutor::trip(std::size_t index, std::size_t guard) {
  Scope& scope = scopes_[index];
  const GuardPoll& g = scope.guards[guard];
  GuardTrip event{scope.instance, scope.net, g.spec.name, g.spec.terms[g.term].text, {}, {}, now()};
  for (std::size_t i = scope.depth; i < phases_.size(); ++i) {
    event.preempted_phases.push_back(fmt::format("{} (instance {})", phases_[i].name, phases_[i].instance));
  }
  // The calls in flight in the scope, in the order issued: the rules' own
  // (they wait in the scope), and the polls of its guards and of the scopes inside it.
  std::vector<std::pair<ActionId, std::string>> calls;
  if (in_flight_ != 0) {
    const tactical::Primitive* p = catalogue_.find(pending_name_);
    calls.emplace_back(in_flight_,
                       fmt::format("{} {}", core::call_verb_name(p ? p->kind : core::CallVerb::Exec), pending_name_));
    forgotten_.insert(in_flight_);
    in_flight_ = 0;
  }
  for (const auto& [id, call] : guard_calls_) {
    if (const Scope* s = find_scope(call.scope); s && s - scopes_.data() >= static_cast<std::ptrdiff_t>(index)) {
      calls.emplace_back(id, call.text);
    }
  }
  std::sort(calls.begin(), calls.end());
  for (auto& [id, text] : calls) event.preempted_calls.push_back(std::move(text));
  stop_guards(index);
  scopes_.erase(scopes_.begin() + static_cast<std::ptrdiff_t>(index) + 1, scopes_.end());
  scopes_[index].tripped = std::string(event.guard);
  // The observers hear the trip, then the phases inside the scope end
  // (innermost first), as the CORAL Engine tells them; then the rules,
  // resumed, unwind to the scope's handler.
  observers_.guard_tripped(event);
  while (phases_.size() > scopes_[index].depth) {
    PhaseEnd end{phases_.back().instance, phases_.back().name, "", 0, true, now()};
    observers_.phase_ended(end);
    phases_.pop_back();
  }
  resume();
}

void PrologExecutor::stop_guards(std::size_t from) {
  for (std::size_t i = from; i < scopes_.size(); ++i) {
    for (GuardPoll& g : scopes_[i].guards) {
      if (g.in_flight == 0) continue;
      guard_calls_.erase(g.in_flight);
      forgotten_.insert(g.in_flight);
      g.in_flight = 0;
    }
  }
}

}  // namespace strata::strategic
