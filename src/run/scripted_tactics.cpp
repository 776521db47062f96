#include "run/scripted_tactics.h"

#include <fmt/format.h>

namespace strata::run {

ScriptedTactics::ScriptedTactics(strategic::Tactics& inner, asio::io_context& io, AnswerScript script,
                                 tactical::MissionLog* log, std::function<void(const std::string&)> on_diverge)
    : inner_(inner),
      io_(io),
      script_(std::move(script)),
      log_(log),
      on_diverge_(std::move(on_diverge)),
      used_(script_.answers.size(), false) {}

std::optional<std::size_t> ScriptedTactics::next_of(const std::string& net) const {
  if (net.empty()) return std::nullopt;
  for (std::size_t i = 0; i < used_.size(); ++i) {
    if (!used_[i] && script_.answers[i].net == net) return i;
  }
  return std::nullopt;
}

std::string ScriptedTactics::first_unused() const {
  for (std::size_t i = 0; i < used_.size(); ++i) {
    if (!used_[i]) return script_.answers[i].where();
  }
  return {};
}

void ScriptedTactics::diverge(const std::string& why) {
  if (!diverged_.empty()) return;
  diverged_ = why;
  if (log_) {
    log_->write({{"event", "answers_diverged"},
                 {"reason", why},
                 {"used", used_count_},
                 {"sim_time", tactical::log_time(inner_.sim_time_s())}});
  }
  if (on_diverge_) on_diverge_(why);
}

void ScriptedTactics::withhold(std::string_view name, tactical::CallHandler&& done) {
  asio::post(io_, [done = std::move(done), what = std::string(name)] {
    done(tactical::CallError{tactical::CallError::Kind::Withheld, std::nullopt,
                             fmt::format("{} not sent: the run left the scripted answers", what)});
  });
}

void ScriptedTactics::phase_started(const strategic::PhaseStart& e) {
  instances_[e.instance] = Instance{std::string(e.name), std::string(e.caller), e.parent};
}

void ScriptedTactics::action_started(const strategic::ActionStart& e) {
  pending_.reset();
  if (e.is_phase() || e.is_call(core::CallVerb::Report)) return;
  auto it = instances_.find(e.instance);
  pending_ = Pending{it == instances_.end() ? std::string() : it->second.net, std::string(e.transition),
                     std::string(e.kind_name()), std::string(e.primitive)};
}

void ScriptedTactics::phase_ended(const strategic::PhaseEnd& e) {
  auto it = instances_.find(e.instance);
  if (it == instances_.end()) return;
  const Instance inst = it->second;
  instances_.erase(it);
  if (e.cancelled || !diverged_.empty()) return;
  auto parent = instances_.find(inst.parent);
  if (parent == instances_.end()) return;  // the mission itself
  auto next = next_of(parent->second.net);
  if (!next) return;
  const ScriptedAnswer& a = script_.answers[*next];
  if (a.action != "phase" || a.primitive != e.name || a.transition != inst.caller) return;
  if (a.exit != e.exit) {
    diverge(
        fmt::format("phase {} (run by {} of {}) ended at '{}', where the script has '{}' ({}); the phase's own "
                    "answers are not in the script, so the vehicle's decided its end",
                    e.name, inst.caller, parent->second.net, e.exit, a.exit, a.where()));
    return;
  }
  used_[*next] = true;
  ++used_count_;
  if (log_) {
    log_->write({{"event", "scripted_phase"},
                 {"answer_index", a.index},
                 {"step", a.step},
                 {"net", a.net},
                 {"transition", a.transition},
                 {"phase", a.primitive},
                 {"exit", a.exit},
                 {"sim_time", tactical::log_time(e.sim_time_s)}});
  }
}

void ScriptedTactics::call(std::string_view name, std::vector<tactical::Value> args, tactical::CallHandler done) {
  std::optional<Pending> p = std::move(pending_);
  pending_.reset();
  if (!diverged_.empty()) {
    withhold(name, std::move(done));
    return;
  }
  if (!p || p->primitive != name) {
    inner_.call(name, std::move(args), std::move(done));
    return;
  }
  std::optional<std::size_t> entry;
  if (auto next = next_of(p->net)) {
    const ScriptedAnswer& a = script_.answers[*next];
    if (a.action != p->kind || a.primitive != p->primitive ||
        (!a.transition.empty() && a.transition != p->transition)) {
      diverge(fmt::format("{} {} (transition {} of {}) was called where the script has {}", p->kind, p->primitive,
                          p->transition, p->net, a.where()));
      withhold(name, std::move(done));
      return;
    }
    entry = next;
  } else {
    for (std::size_t i = 0; i < used_.size() && !entry; ++i) {
      const ScriptedAnswer& a = script_.answers[i];
      if (!used_[i] && a.net.empty() && a.action == p->kind && a.primitive == p->primitive) entry = i;
    }
  }
  if (!entry) {
    inner_.call(name, std::move(args), std::move(done));
    return;
  }
  used_[*entry] = true;
  ++used_count_;
  const ScriptedAnswer a = script_.answers[*entry];
  inner_.call(name, std::move(args), [this, a, done = std::move(done)](tactical::CallResult r) {
    // An error (the vehicle refused the call, the link is gone) stands: the
    // script says what a call answered, not that it could be made.
    if (!r) {
      done(std::move(r));
      return;
    }
    tactical::CallOutcome o = r.value();
    const bool vehicle = o.value;
    o.value = a.value;
    if (log_) {
      log_->write({{"event", "scripted_answer"},
                   {"answer_index", a.index},
                   {"step", a.step},
                   {"net", a.net},
                   {"transition", a.transition},
                   {"action", a.action},
                   {"primitive", a.primitive},
                   {"vehicle", vehicle ? 1 : 0},
                   {"answer", a.value ? 1 : 0},
                   {"sim_time", tactical::log_time(o.sim_time_s)}});
    }
    done(o);
  });
}

}  // namespace strata::run
