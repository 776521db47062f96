#include "protocol/fields.h"

#include <charconv>
#include <cmath>
#include <system_error>

#include <fmt/format.h>

namespace strata::protocol {
namespace {

bool is_printable(char c) { return c >= 0x20 && c <= 0x7e; }
bool is_digit(char c) { return c >= '0' && c <= '9'; }

std::string describe_byte(char c) {
  return fmt::format("0x{:02x}", static_cast<unsigned>(static_cast<unsigned char>(c)));
}

// The escaped form of one byte inside quotes.
std::string_view escaped(const char& c) {
  switch (c) {
    case '"': return "\\\"";
    case '\\': return "\\\\";
    case '\n': return "\\n";
    case '\t': return "\\t";
    default: break;
  }
  if (!is_printable(c)) return "?";
  return {&c, 1};
}

// Reads a quoted field starting at line[pos] == '"'. On success pos is past
// the closing quote.
bool read_quoted(std::string_view line, std::size_t& pos, Field& field, std::string& error) {
  std::size_t start = pos++;
  while (pos < line.size()) {
    char c = line[pos];
    if (!is_printable(c)) {
      error = fmt::format("byte {} at column {} is not printable ASCII", describe_byte(c), pos + 1);
      return false;
    }
    if (c == '"') {
      ++pos;
      return true;
    }
    if (c == '\\') {
      if (pos + 1 >= line.size()) break;
      char e = line[pos + 1];
      switch (e) {
        case '"': field.text += '"'; break;
        case '\\': field.text += '\\'; break;
        case 'n': field.text += '\n'; break;
        case 't': field.text += '\t'; break;
        default:
          if (is_printable(e)) {
            error = fmt::format("bad escape '\\{}' at column {} (only \\\" \\\\ \\n \\t)", e, pos + 1);
          } else {
            error = fmt::format("byte {} at column {} is not printable ASCII", describe_byte(e), pos + 2);
          }
          return false;
      }
      pos += 2;
      continue;
    }
    field.text += c;
    ++pos;
  }
  error = fmt::format("unterminated quoted string starting at column {}", start + 1);
  return false;
}

bool read_bare(std::string_view line, std::size_t& pos, Field& field, std::string& error) {
  std::size_t start = pos;
  while (pos < line.size() && line[pos] != ' ') {
    char c = line[pos];
    if (!is_printable(c)) {
      error = fmt::format("byte {} at column {} is not printable ASCII", describe_byte(c), pos + 1);
      return false;
    }
    if (!is_bare_char(c)) {
      error = fmt::format("character '{}' at column {} is not allowed outside quotes", c, pos + 1);
      return false;
    }
    ++pos;
  }
  field.text.assign(line.substr(start, pos - start));
  return true;
}

// Matches the number grammar of fields.h; sets is_float when there is a
// fraction or an exponent.
bool is_number_syntax(std::string_view s, bool& is_float) {
  std::size_t i = 0;
  auto digits = [&] {
    std::size_t from = i;
    while (i < s.size() && is_digit(s[i])) ++i;
    return i > from;
  };
  is_float = false;
  if (i < s.size() && s[i] == '-') ++i;
  if (!digits()) return false;
  if (i < s.size() && s[i] == '.') {
    ++i;
    is_float = true;
    if (!digits()) return false;
  }
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    is_float = true;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
    if (!digits()) return false;
  }
  return i == s.size();
}

}  // namespace

bool is_bare_char(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || is_digit(c) || c == '_' || c == '.' || c == ':' ||
         c == '+' || c == '-' || c == '/' || c == '=';
}

bool is_bare_token(std::string_view text) {
  if (text.empty()) return false;
  for (char c : text) {
    if (!is_bare_char(c)) return false;
  }
  return true;
}

SplitResult split_fields(std::string_view line) {
  SplitResult out;
  std::size_t pos = 0;
  while (true) {
    while (pos < line.size() && line[pos] == ' ') ++pos;
    if (pos >= line.size()) break;
    if (out.fields.size() == kMaxFields) {
      out.error = fmt::format("more than {} fields", kMaxFields);
      return out;
    }
    Field field;
    field.column = pos + 1;
    if (line[pos] == '"') {
      field.quoted = true;
      if (!read_quoted(line, pos, field, out.error)) return out;
      if (pos < line.size() && line[pos] != ' ') {
        out.error = fmt::format("a quoted string must be followed by a space (column {})", pos + 1);
        return out;
      }
    } else if (!read_bare(line, pos, field, out.error)) {
      return out;
    }
    out.fields.push_back(std::move(field));
  }
  if (out.fields.empty()) out.error = "empty line";
  return out;
}

std::string quote(std::string_view text) {
  std::string out;
  out.reserve(text.size() + 2);
  out += '"';
  for (const char& c : text) out += escaped(c);
  out += '"';
  return out;
}

std::string quote_within(std::string_view text, std::size_t max_bytes) {
  std::string full = quote(text);
  if (full.size() <= max_bytes) return full;
  constexpr std::string_view kEllipsis = "...";
  // Room for the opening quote, the ellipsis and the closing quote.
  std::size_t budget = max_bytes < 5 ? 0 : max_bytes - 2 - kEllipsis.size();
  std::string out = "\"";
  for (const char& c : text) {
    std::string_view e = escaped(c);
    if (out.size() - 1 + e.size() > budget) break;
    out += e;
  }
  out += kEllipsis;
  out += '"';
  return out;
}

std::string bare_or_quoted(std::string_view text) { return is_bare_token(text) ? std::string(text) : quote(text); }

std::string format_double(double d) {
  std::string s = fmt::format("{}", d);
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

core::Result<Value> parse_number(std::string_view token) {
  bool is_float = false;
  if (!is_number_syntax(token, is_float)) {
    return core::make_error(core::ErrorCode::InvalidInput, fmt::format("'{}' is not a decimal number", token));
  }
  const char* first = token.data();
  const char* last = token.data() + token.size();
  if (!is_float) {
    std::int64_t i = 0;
    auto [ptr, ec] = std::from_chars(first, last, i);
    if (ec != std::errc() || ptr != last) {
      return core::make_error(core::ErrorCode::Overflow, fmt::format("integer '{}' is out of range", token));
    }
    return Value::integer(i);
  }
  double d = 0.0;
  auto [ptr, ec] = std::from_chars(first, last, d, std::chars_format::general);
  if (ec != std::errc() || ptr != last || !std::isfinite(d)) {
    return core::make_error(core::ErrorCode::Overflow, fmt::format("number '{}' is out of range", token));
  }
  return Value::real(d);
}

std::optional<double> parse_double(std::string_view token) {
  core::Result<Value> v = parse_number(token);
  if (!v.ok()) return std::nullopt;
  return v.value().number();
}

std::optional<RequestId> parse_id(std::string_view token, bool allow_zero) {
  if (token.empty()) return std::nullopt;
  for (char c : token) {
    if (!is_digit(c)) return std::nullopt;
  }
  RequestId id = 0;
  auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), id);
  if (ec != std::errc() || ptr != token.data() + token.size()) return std::nullopt;
  if (id > kMaxRequestId || (id == 0 && !allow_zero)) return std::nullopt;
  return id;
}

}  // namespace strata::protocol
