#pragma once
// The Tactics a run gives its executor when its answers are scripted
// (`strata run --answers FILE`, answers.h): every call still goes to the
// vehicle (which carries it out, and time passes as in any run), but a call
// the script names gets the script's answer instead of the vehicle's. It is
// also an observer of the executor: the executor tells observers of each
// action before it calls it, which is how a call is known by its net and
// transition.
//
// Matching: entries naming a net are taken in file order per net: a call
// from that net (exec, ask, ood) must be its next unused entry, and a phase
// it runs must end at its next entry's exit; anything else is the run
// leaving the witness (on_diverge, once). A net with no unused entries left
// runs on the vehicle's answers. Entries naming no net answer the next call
// of their primitive, whichever net or rule makes it; other calls pass.
//
// Threads: the run's loop only.
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <asio.hpp>

#include "run/answers.h"
#include "strategic/executor.h"
#include "strategic/tactics.h"
#include "tactical/mission_log.h"

namespace strata::run {

class ScriptedTactics final : public strategic::Tactics, public strategic::Observer {
 public:
  // inner, io and log (may be null) must outlive this object. on_diverge is
  // called once, on the loop, with why the run left the script; from then
  // on no call reaches the vehicle (each is answered, from io, with an
  // error), so nothing past the divergence happens before the run's stop
  // (which on_diverge requests) ends the mission.
  ScriptedTactics(strategic::Tactics& inner, asio::io_context& io, AnswerScript script, tactical::MissionLog* log,
                  std::function<void(const std::string&)> on_diverge);

  void call(std::string_view name, std::vector<tactical::Value> args, tactical::CallHandler done) override;
  double sim_time_s() const override { return inner_.sim_time_s(); }

  void phase_started(const strategic::PhaseStart& e) override;
  void phase_ended(const strategic::PhaseEnd& e) override;
  void action_started(const strategic::ActionStart& e) override;

  std::size_t used() const { return used_count_; }
  std::size_t total() const { return script_.answers.size(); }
  const std::string& diverged() const { return diverged_; }
  const AnswerScript& script() const { return script_; }
  // The first entry not used, for people ("" when all were).
  std::string first_unused() const;

 private:
  struct Pending {
    std::string net, transition, kind, primitive;
  };
  // The next unused entry naming `net`; nullopt when none is left.
  std::optional<std::size_t> next_of(const std::string& net) const;
  void diverge(const std::string& why);
  // After the divergence: the call is not sent; done gets an error, posted.
  void withhold(std::string_view name, tactical::CallHandler&& done);

  strategic::Tactics& inner_;
  asio::io_context& io_;
  AnswerScript script_;
  tactical::MissionLog* log_;
  std::function<void(const std::string&)> on_diverge_;
  std::vector<bool> used_;
  std::size_t used_count_ = 0;
  std::string diverged_;
  struct Instance {
    std::string net, caller;
    strategic::InstanceId parent = 0;
  };
  std::map<strategic::InstanceId, Instance> instances_;
  std::optional<Pending> pending_;
};

}  // namespace strata::run
