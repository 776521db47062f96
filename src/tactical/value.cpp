#include "tactical/value.h"

#include <charconv>
#include <limits>

#include <fmt/format.h>

namespace strata::tactical {

Value Value::from_literal(const coral::ast::Literal& literal) {
  if (literal.kind == coral::ast::Literal::Kind::String) return of(literal.value);
  double n = 0;
  const char* first = literal.value.data();
  const char* last = first + literal.value.size();
  if (!literal.value.empty() && *first == '+') ++first;  // from_chars takes no '+'
  auto [end, ec] = std::from_chars(first, last, n);
  if (ec != std::errc() || end != last) n = std::numeric_limits<double>::quiet_NaN();
  return of(n);
}

std::string to_string(const Value& value) {
  if (value.type == Value::Type::String) return value.text;
  if (value.number == 0) return "0";  // not "-0"
  return fmt::format("{}", value.number);
}

}  // namespace strata::tactical
