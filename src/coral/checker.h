#pragma once
// Semantic checks over a whole load (the root file and its imports): names,
// TACTIC and PHASE shapes, the mission library, and structural warnings.
// See docs/language.md for the list of checks.
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "coral/ast.h"
#include "coral/loader.h"
#include "core/diagnostic.h"

namespace strata::coral {

// What the checker needs to know of a vehicle primitive. The catalogue lives
// in the Tactical level; the checker sees it only through this lookup.
struct ArgumentSignature {
  std::string name;
  bool is_number = true;      // false: a string
  std::string unit;           // "m", "deg"; "" for none
  std::optional<double> min;  // inclusive; numbers only
  std::optional<double> max;  // inclusive; numbers only
};

struct PrimitiveSignature {
  ast::TacticType kind = ast::TacticType::Exec;
  std::size_t min_args = 0;
  std::size_t max_args = 0;
  // One per argument, in call order (max_args of them), or empty when the
  // lookup does not know them: then only the count is checked.
  std::vector<ArgumentSignature> args;
  // Why the vehicle the mission is checked for cannot carry it out, as a
  // sentence ("an IMC vehicle has no scanning sonar ..."); nullopt when it
  // can. Each call of such a primitive is a PrimitiveUnavailable error.
  std::optional<std::string> unavailable = std::nullopt;
};

struct CheckOptions {
  // When set, every EXEC/ASK/OOD primitive must be known to it.
  std::function<std::optional<PrimitiveSignature>(std::string_view)> primitive;
  // Every known primitive name, for "did you mean" notes.
  std::vector<std::string> primitive_names;
  // The vehicle the signatures' `unavailable` speak of, for messages:
  // "an IMC vehicle".
  std::string execution_level;
};

void check(const Load& load, core::DiagnosticSink& sink, const CheckOptions& options = {});

}  // namespace strata::coral
