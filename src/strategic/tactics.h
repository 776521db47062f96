#pragma once
// What a Strategic level calls below it: vehicle primitives by name, each
// answered later with 1 or 0 (paper §2.1). The CORAL Engine and the PROLOG
// executor call only this, so both issue the same primitive calls; tests put
// a scripted fake here, runs put the Tactical level.
//
// Threads: one; call on the event loop's thread.
#include <string_view>
#include <vector>

#include "tactical/tactical_level.h"
#include "tactical/value.h"

namespace strata::strategic {

class Tactics {
 public:
  virtual ~Tactics() = default;
  // Calls primitive `name`. done is called exactly once, from the event
  // loop and never inside call(): with the outcome or with an error.
  virtual void call(std::string_view name, std::vector<tactical::Value> args, tactical::CallHandler done) = 0;
  // The same for a guard's own poll (its sleep or an ask of its condition),
  // so the Tactical level's record says whose call it was. By default a
  // plain call.
  virtual void guard_call(std::string_view guard, std::string_view name, std::vector<tactical::Value> args,
                          tactical::CallHandler done) {
    (void)guard;
    call(name, std::move(args), std::move(done));
  }
  // The vehicle's time as last heard, in simulated seconds.
  virtual double sim_time_s() const = 0;
};

// The Tactical level behind the interface. It must outlive this object.
class TacticalTactics final : public Tactics {
 public:
  explicit TacticalTactics(tactical::TacticalLevel& level) : level_(level) {}
  void call(std::string_view name, std::vector<tactical::Value> args, tactical::CallHandler done) override {
    level_.call(name, std::move(args), std::move(done));
  }
  void guard_call(std::string_view guard, std::string_view name, std::vector<tactical::Value> args,
                  tactical::CallHandler done) override {
    level_.call(name, std::move(args), std::move(done), guard);
  }
  double sim_time_s() const override { return level_.sim_time_s(); }

 private:
  tactical::TacticalLevel& level_;
};

}  // namespace strata::strategic
