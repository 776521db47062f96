#pragma once
// For the Strategic level's tests: a Tactical level the test answers by
// hand. Calls are queued, never answered inside call(); each test suite
// adds the answering policy it needs (the oldest call for the CORAL Engine,
// the one the rules wait for in PROLOG).
#include <algorithm>
#include <deque>
#include <string>
#include <string_view>
#include <vector>

#include "strategic/tactics.h"

namespace strata::strategic::testing {

struct FakeTacticsBase : Tactics {
  struct Call {
    std::string name;
    std::vector<tactical::Value> args;
    tactical::CallHandler done;
  };
  void call(std::string_view name, std::vector<tactical::Value> args, tactical::CallHandler done) override {
    calls.push_back({std::string(name), std::move(args), std::move(done)});
    pending.push_back(calls.size() - 1);
  }
  double sim_time_s() const override { return time_s; }

  // Call i's handler, taken out of the pending calls.
  tactical::CallHandler take(std::size_t i) {
    pending.erase(std::find(pending.begin(), pending.end(), i));
    return std::move(calls[i].done);
  }
  // "f1 f2(1) report(text)"
  std::string names() const {
    std::string out;
    for (const Call& c : calls) {
      if (!out.empty()) out += ' ';
      out += c.name;
      for (std::size_t k = 0; k < c.args.size(); ++k) out += (k == 0 ? "(" : ",") + tactical::to_string(c.args[k]);
      if (!c.args.empty()) out += ')';
    }
    return out;
  }

  std::vector<Call> calls;
  std::deque<std::size_t> pending;
  double time_s = 0.0;
};

}  // namespace strata::strategic::testing
