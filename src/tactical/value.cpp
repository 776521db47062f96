#include "tactical/value.h"

#include <fmt/format.h>

namespace strata::tactical {

std::string to_string(const Value& value) {
  if (value.type == Value::Type::String) return value.text;
  if (value.number == 0) return "0";  // not "-0"
  return fmt::format("{}", value.number);
}

}  // namespace strata::tactical
