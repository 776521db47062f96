#pragma once
// What `strata primitives` prints: the catalogue as a table for people, or
// as JSON for tools.
#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

#include "tactical/catalogue.h"

namespace strata::tactical {

// One row per primitive, in catalogue order: name, kind, arguments with units
// and ranges, reply timeout, PROLOG call, message, doc. Columns are
// aligned; the last line says where the catalogue came from.
std::string format_catalogue(const Catalogue& catalogue);

// {"source": ..., "primitives": [{"name", "kind", "args": [{"name", "type",
// "unit", "min"?, "max"?, "default"?}], "timeout_s"?, "timeout_plus_arg"?,
// "data"?, "prolog" (the predicate indicator, "exec_sleep/2"), "doc",
// "message"?}]}. Optional keys are left out when unset.
nlohmann::ordered_json catalogue_json(const Catalogue& catalogue);

// "seconds (s, 0.1..3600)", "text (string)": one argument for the table.
std::string describe_argument(const Argument& arg);

}  // namespace strata::tactical
