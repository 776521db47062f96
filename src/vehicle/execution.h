#pragma once
// The Execution level's function table: what `exec`, `ask` and `ood`
// requests may name, with their arguments, and how each maps onto the
// Simulation. This table is the vehicle's side of the Tactical primitives;
// `strata vehicle --interface` prints it.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "protocol/message.h"
#include "vehicle/simulation.h"

namespace strata::vehicle {

struct FunctionArg {
  std::string name;
  std::string unit;
};

struct FunctionSpec {
  protocol::Verb verb;  // Exec, Ask or Ood
  std::string name;
  std::vector<FunctionArg> args;
  std::string doc;
};

const std::vector<FunctionSpec>& function_table();
const FunctionSpec* find_function(protocol::Verb verb, std::string_view name);

// The outcome of one exec/ask/ood on the simulation.
struct Outcome {
  // Set when the request cannot be taken at all (unknown function, bad
  // arguments): the server answers `err ID CODE "message"`.
  std::optional<protocol::ErrorCode> refused;
  bool value = false;    // done: executed; answer: the predicate
  std::string message;   // why it was refused or failed
  double sleep_s = 0.0;  // `sleep`: seconds the caller must let pass before replying
};

// Runs request (exec, ask or ood) on sim at its current time. Does not step
// time; `sleep` only reports how long to wait.
Outcome execute(Simulation& sim, const protocol::Request& request);

// Every message the vehicle accepts and emits, and the function table, as
// text for `strata vehicle --interface`.
std::string interface_text();

}  // namespace strata::vehicle
