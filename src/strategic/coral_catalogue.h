#pragma once
// Where the CORAL language meets the primitive catalogue. coral and tactical
// are siblings under the Strategic level and neither includes the other
// (docs/architecture.md): the CORAL checker sees primitives only through
// coral::CheckOptions, the Tactical level takes arguments only as
// tactical::Values. This adapter builds the one from the catalogue and turns
// CORAL literals into the other.
#include "coral/ast.h"
#include "coral/checker.h"
#include "tactical/catalogue.h"
#include "tactical/execution_level.h"
#include "tactical/value.h"

namespace strata::strategic {

// The lookup and the names the CORAL checker needs. The options hold their
// own copy of the signatures: they stay valid when the catalogue is gone.
// With an Execution level other than the Phoenix protocol, a primitive it
// cannot carry out (tactical::unavailable_on) is refused at each call.
coral::CheckOptions coral_check_options(const tactical::Catalogue& catalogue,
                                        tactical::ExecutionLevel level = tactical::ExecutionLevel::Phoenix);

// Integer and Float literals become numbers (a literal that does not read as
// a number becomes NaN, which tactical::render() rejects); String literals
// become their unescaped value.
tactical::Value value_of(const coral::ast::Literal& literal);

}  // namespace strata::strategic
