#pragma once
// Literal numbers in the primitive calls of PROLOG rules, checked against
// the catalogue's ranges before the rules run (docs/prolog.md, section 4):
// `exec_heading(400, X)` is reported at check with its line and column, as
// CORAL's `heading(400)` is (ArgumentOutOfRange). The scan reads the rule
// text itself (quoted text and comments skipped), so it sees the numbers as
// written; an argument that is not a literal number (a variable, an
// expression, a term) is the rules' business and is checked when the call
// is made. The same scan finds the calls of primitives that the vehicle a
// mission is checked for cannot carry out (PrimitiveUnavailable).
#include <string_view>
#include <vector>

#include "strategic/prolog_rules_scan.h"
#include "tactical/catalogue.h"
#include "tactical/execution_level.h"

namespace strata::strategic {

// Every literal number given to exec_<name>(...) or ask_<name>(...) (a
// primitive of that kind in catalogue) outside the range of its argument,
// or not finite; in text order. A call with more arguments than the
// primitive takes is left to the check of arities.
std::vector<RulesScanProblem> scan_primitive_arguments(std::string_view text, const tactical::Catalogue& catalogue);

// Every call of a primitive of catalogue that `level` cannot carry out
// (tactical::unavailable_on): exec_<name>(...) and ask_<name>(...) of a
// primitive of that kind, and ood('<name>', ...); each at the first
// character of the called name, in text order, saying which and why:
// "'start_sonar' is not available on an IMC vehicle: ...". Nothing for the
// Phoenix protocol.
std::vector<RulesScanProblem> scan_unavailable_primitives(std::string_view text, const tactical::Catalogue& catalogue,
                                                          tactical::ExecutionLevel level);

}  // namespace strata::strategic
