#pragma once
// One mission log line written field by field: byte for byte what dumping
// an nlohmann::ordered_json with the same fields in the same order gives
// (MissionLog's dump: compact, UTF-8 kept, invalid UTF-8 replaced), without
// building one. The run's busiest lines (telemetry, request, reply, fire,
// mark) are written this way; the rest are built as JSON values.
#include <concepts>
#include <string>
#include <string_view>
#include <type_traits>

#include <nlohmann/json.hpp>

namespace strata::tactical {

class LogLine {
 public:
  // {"event":"EVENT"
  explicit LogLine(std::string_view event);

  // A number: doubles as nlohmann writes them (shortest round trip, "2.0"
  // for an integral value, null when not finite).
  LogLine& add(std::string_view key, double value);
  template <std::integral T>
  requires(!std::same_as<T, bool>) LogLine& add(std::string_view key, T value) {
    if constexpr (std::is_signed_v<T>) {
      if (value < 0) return add_integer(key, true, static_cast<unsigned long long>(-(value + 1)) + 1ULL);
    }
    return add_integer(key, false, static_cast<unsigned long long>(value));
  }
  LogLine& add(std::string_view key, std::string_view text);
  LogLine& add(std::string_view key, const char* text) { return add(key, std::string_view(text)); }
  LogLine& add(std::string_view key, const std::string& text) { return add(key, std::string_view(text)); }
  LogLine& add(std::string_view key, const nlohmann::ordered_json& value);
  LogLine& add_null(std::string_view key);
  // An object's fields follow, up to its end_object().
  LogLine& begin_object(std::string_view key);
  LogLine& end_object();

  // The line with its closing brace and newline; the line is spent.
  std::string finish() &&;

 private:
  LogLine& add_integer(std::string_view key, bool negative, unsigned long long magnitude);
  void key(std::string_view k);
  void string(std::string_view s);

  std::string text_;
  bool first_ = false;  // the next field is the first of its object
  int open_ = 0;        // objects begun and not ended
};

}  // namespace strata::tactical
