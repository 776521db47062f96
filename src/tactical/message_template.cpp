#include "tactical/message_template.h"

#include <fmt/format.h>

namespace strata::tactical {

namespace {

bool is_ident_start(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; }
bool is_ident_char(char c) { return is_ident_start(c) || (c >= '0' && c <= '9'); }

core::Error syntax(std::string message) { return core::make_error(core::ErrorCode::InvalidInput, std::move(message)); }

}  // namespace

bool is_identifier(std::string_view text) {
  if (text.empty() || !is_ident_start(text[0])) return false;
  for (char c : text) {
    if (!is_ident_char(c)) return false;
  }
  return true;
}

core::Result<MessageTemplate> parse_message_template(std::string_view message) {
  MessageTemplate out;
  std::size_t i = 0;
  while (i < message.size()) {
    if (message[i] == ' ') {
      ++i;
      continue;
    }
    auto c = static_cast<unsigned char>(message[i]);
    if (c < 0x20 || c == 0x7f) {
      return syntax(fmt::format("message holds a control character at byte {}", i + 1));
    }
    TemplateField field;
    std::string literal;
    while (i < message.size() && message[i] != ' ') {
      char ch = message[i];
      auto u = static_cast<unsigned char>(ch);
      if (u < 0x20 || u == 0x7f) {
        return syntax(fmt::format("message holds a control character at byte {}", i + 1));
      }
      if (ch == '}') return syntax(fmt::format("'}}' without '{{' at byte {} of the message", i + 1));
      if (ch != '{') {
        literal += ch;
        ++i;
        continue;
      }
      std::size_t close = message.find('}', i + 1);
      if (close == std::string_view::npos) {
        return syntax(fmt::format("'{{' at byte {} of the message is never closed", i + 1));
      }
      std::string_view name = message.substr(i + 1, close - i - 1);
      if (!is_identifier(name)) {
        return syntax(
            fmt::format("'{{{}}}' is not a placeholder: write {{name}} with a letter, "
                        "digits and '_'",
                        name));
      }
      if (!literal.empty()) field.pieces.push_back({false, std::move(literal)});
      literal.clear();
      field.pieces.push_back({true, std::string(name)});
      i = close + 1;
    }
    if (!literal.empty()) field.pieces.push_back({false, std::move(literal)});
    out.fields.push_back(std::move(field));
  }
  return out;
}

}  // namespace strata::tactical
