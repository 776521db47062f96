#pragma once
// A literal argument of a primitive call: a number or a string. CORAL
// literals and PROLOG terms both become Values before a call is rendered
// (the Strategic level converts them: strategic/coral_catalogue.h,
// strategic/prolog_mission.cpp).
#include <string>
#include <string_view>

namespace strata::tactical {

struct Value {
  enum class Type { Number, String };

  Type type = Type::Number;
  double number = 0;  // Type::Number
  std::string text;   // Type::String

  static Value of(double n) { return Value{Type::Number, n, {}}; }
  static Value of(std::string s) { return Value{Type::String, 0, std::move(s)}; }
  static Value of(const char* s) { return of(std::string(s)); }

  bool operator==(const Value&) const = default;
};

// Numbers in their shortest round-trip form ("1", "0.5", "1e-07"), the form
// used on the wire; strings as they are.
std::string to_string(const Value& value);

}  // namespace strata::tactical
