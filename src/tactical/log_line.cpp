#include "tactical/log_line.h"

#include <array>
#include <cassert>
#include <charconv>
#include <cmath>

namespace strata::tactical {

LogLine::LogLine(std::string_view event) {
  text_.reserve(160);
  text_ += '{';
  first_ = true;
  add("event", event);
}

void LogLine::key(std::string_view k) {
  if (!first_) text_ += ',';
  first_ = false;
  string(k);
  text_ += ':';
}

void LogLine::string(std::string_view s) {
  // Printable ASCII but the quote and the backslash is written as it is;
  // anything else as nlohmann escapes it (and replaces invalid UTF-8).
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    if (c < 0x20 || c > 0x7e || c == '"' || c == '\\') {
      text_ +=
          nlohmann::ordered_json(std::string(s)).dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
      return;
    }
  }
  text_ += '"';
  text_ += s;
  text_ += '"';
}

LogLine& LogLine::add(std::string_view k, double value) {
  key(k);
  if (!std::isfinite(value)) {
    text_ += "null";
    return *this;
  }
  std::array<char, 64> buf{};
  // The same conversion nlohmann's serializer makes of a double.
  const char* end = nlohmann::detail::to_chars(buf.data(), buf.data() + buf.size(), value);
  text_.append(buf.data(), static_cast<std::size_t>(end - buf.data()));
  return *this;
}

LogLine& LogLine::add_integer(std::string_view k, bool negative, unsigned long long magnitude) {
  key(k);
  if (negative) text_ += '-';
  std::array<char, 24> buf{};
  const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), magnitude);
  text_.append(buf.data(), r.ptr);
  return *this;
}

LogLine& LogLine::add(std::string_view k, std::string_view text) {
  key(k);
  string(text);
  return *this;
}

LogLine& LogLine::add(std::string_view k, const nlohmann::ordered_json& value) {
  key(k);
  text_ += value.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
  return *this;
}

LogLine& LogLine::add_null(std::string_view k) {
  key(k);
  text_ += "null";
  return *this;
}

LogLine& LogLine::begin_object(std::string_view k) {
  key(k);
  text_ += '{';
  first_ = true;
  ++open_;
  return *this;
}

LogLine& LogLine::end_object() {
  assert(open_ > 0);
  text_ += '}';
  first_ = false;
  --open_;
  return *this;
}

std::string LogLine::finish() && {
  assert(open_ == 0);
  text_ += "}\n";
  return std::move(text_);
}

}  // namespace strata::tactical
