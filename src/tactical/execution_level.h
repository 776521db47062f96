#pragma once
// The Execution levels a run can reach (docs/imc.md, docs/protocol.md)
// and which primitives each one carries out.
// The Phoenix protocol carries every primitive of the catalogue it was
// written for; an IMC vehicle (LSTS DUNE, or `strata vehicle --imc`)
// carries those in the table of docs/imc.md and refuses the rest, which
// `strata check --vehicle imc://...` and `strata run` report at the call's
// place in the mission, before anything moves.
#include <optional>
#include <string>
#include <string_view>

#include "protocol/message.h"
#include "tactical/catalogue.h"

namespace strata::tactical {

enum class ExecutionLevel { Phoenix, Imc };

// "the Phoenix protocol", "an IMC vehicle": for messages.
std::string_view execution_level_name(ExecutionLevel level);

// The execution level a --vehicle value names: "imc://HOST:PORT" (or
// "imc://HOST:PORT/ID") is IMC; anything else ("HOST:PORT", "") the
// Phoenix protocol.
ExecutionLevel execution_level_of(std::string_view vehicle);

// How an IMC vehicle carries out one wire function (the second field of a
// primitive's message: `exec goto_xy {x_m} {y_m}` is goto_xy).
enum class ImcMapping {
  Reference,  // a Reference in the FollowReference plan (goto_xy, goto_depth, ...)
  Local,      // kept by the link on the vehicle's clock (sleep, timers, setpoints)
  State,      // an ask answered from the vehicle's own messages
  Plan,       // the plan's start and end (start_network, shutdown_network)
  Payload,    // a payload switched on or off (SetEntityParameters: the sonar)
};
// nullopt: an IMC vehicle has nothing for it.
std::optional<ImcMapping> imc_mapping(protocol::Verb verb, std::string_view function);

// Whether `primitive` can be carried out on `level`: nullopt if it can,
// else why not, as a sentence ("an IMC vehicle has no scanning sonar").
// A report is carried out on every level (it never reaches the vehicle).
std::optional<std::string> unavailable_on(ExecutionLevel level, const Primitive& primitive);

}  // namespace strata::tactical
