#include "coral/lexer.h"

#include <array>
#include <cctype>
#include <utility>

#include <fmt/format.h>

namespace strata::coral {
namespace {

bool is_ident_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool is_ident_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }
bool is_digit(char c) { return c >= '0' && c <= '9'; }

constexpr std::array<std::pair<std::string_view, TokenKind>, 14> kKeywords = {{
    {"net", TokenKind::KwNet},
    {"mission", TokenKind::KwMission},
    {"place", TokenKind::KwPlace},
    {"exit", TokenKind::KwExit},
    {"transition", TokenKind::KwTransition},
    {"priority", TokenKind::KwPriority},
    {"wait", TokenKind::KwWait},
    {"action", TokenKind::KwAction},
    {"signal", TokenKind::KwSignal},
    {"data", TokenKind::KwData},
    {"import", TokenKind::KwImport},
    {"TACTIC", TokenKind::KwTactic},
    {"PHASE", TokenKind::KwPhase},
    {"guard", TokenKind::KwGuard},
}};

std::string describe_byte(char c) {
  auto u = static_cast<unsigned char>(c);
  if (u >= 0x21 && u < 0x7f) return fmt::format("'{}'", c);
  return fmt::format("byte 0x{:02x}", u);
}

}  // namespace

std::string_view token_kind_name(TokenKind kind) {
  switch (kind) {
    case TokenKind::Identifier: return "a name";
    case TokenKind::Integer: return "an integer";
    case TokenKind::Float: return "a number";
    case TokenKind::String: return "a string";
    case TokenKind::LBrace: return "'{'";
    case TokenKind::RBrace: return "'}'";
    case TokenKind::LParen: return "'('";
    case TokenKind::RParen: return "')'";
    case TokenKind::Comma: return "','";
    case TokenKind::Semicolon: return "';'";
    case TokenKind::Equals: return "'='";
    case TokenKind::Star: return "'*'";
    case TokenKind::EndOfFile: return "end of file";
    default:
      for (const auto& [word, k] : kKeywords) {
        if (k == kind) return word;
      }
  }
  return "?";
}

Lexer::Lexer(core::FileId file, std::string_view text, core::DiagnosticSink& sink)
    : file_(file), text_(text), sink_(sink) {}

core::SourceSpan Lexer::span(std::size_t begin, std::size_t end) const {
  return {file_, static_cast<std::uint32_t>(begin), static_cast<std::uint32_t>(end - begin)};
}

Token Lexer::make(TokenKind kind, std::size_t begin) const {
  return {kind, span(begin, pos_), text_.substr(begin, pos_ - begin)};
}

void Lexer::skip_trivia() {
  while (pos_ < text_.size()) {
    char c = text_[pos_];
    if (c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v') {
      ++pos_;
    } else if (c == '/' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '/') {
      while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    } else if (c == '/' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '*') {
      std::size_t begin = pos_;
      std::size_t end = text_.find("*/", pos_ + 2);
      if (end == std::string_view::npos) {
        sink_.report(core::DiagnosticKind::UnterminatedComment, span(begin, begin + 2),
                     "block comment is not closed by '*/'");
        pos_ = text_.size();
      } else {
        pos_ = end + 2;
      }
    } else {
      return;
    }
  }
}

void Lexer::check_length(const Token& t) {
  if (t.text.size() > kMaxTokenLength) {
    sink_.report(
        core::DiagnosticKind::TokenTooLong, {t.span.file, t.span.offset, 1},
        fmt::format("{} is {} bytes long; the limit is {}", token_kind_name(t.kind), t.text.size(), kMaxTokenLength));
  }
}

Token Lexer::lex_number(std::size_t begin) {
  if (text_[pos_] == '-') ++pos_;
  while (pos_ < text_.size() && is_digit(text_[pos_])) ++pos_;
  TokenKind kind = TokenKind::Integer;
  if (pos_ + 1 < text_.size() && text_[pos_] == '.' && is_digit(text_[pos_ + 1])) {
    kind = TokenKind::Float;
    ++pos_;
    while (pos_ < text_.size() && is_digit(text_[pos_])) ++pos_;
  }
  if (pos_ < text_.size() && (text_[pos_] == 'e' || text_[pos_] == 'E')) {
    std::size_t save = pos_++;
    if (pos_ < text_.size() && (text_[pos_] == '+' || text_[pos_] == '-')) ++pos_;
    if (pos_ < text_.size() && is_digit(text_[pos_])) {
      kind = TokenKind::Float;
      while (pos_ < text_.size() && is_digit(text_[pos_])) ++pos_;
    } else {
      pos_ = save;
    }
  }
  if (pos_ < text_.size() && (is_ident_char(text_[pos_]) || text_[pos_] == '.')) {
    while (pos_ < text_.size() && (is_ident_char(text_[pos_]) || text_[pos_] == '.')) ++pos_;
    Token bad = make(kind, begin);
    bad.malformed = true;
    sink_.report(core::DiagnosticKind::InvalidNumber, bad.span,
                 fmt::format("malformed number '{}'", bad.text.substr(0, 64)));
    return bad;
  }
  Token t = make(kind, begin);
  check_length(t);
  return t;
}

Token Lexer::lex_string(std::size_t begin) {
  ++pos_;  // opening quote
  while (pos_ < text_.size()) {
    char c = text_[pos_];
    if (c == '"') {
      ++pos_;
      Token t = make(TokenKind::String, begin);
      check_length(t);
      return t;
    }
    if (c == '\n') break;
    if (c == '\\') {
      if (pos_ + 1 >= text_.size() || text_[pos_ + 1] == '\n') {
        ++pos_;  // keep the backslash in the token; the string is unterminated, below
        break;
      }
      char e = text_[pos_ + 1];
      if (e != '"' && e != '\\' && e != 'n' && e != 't') {
        auto u = static_cast<unsigned char>(e);
        std::string shown =
            u >= 0x21 && u < 0x7f ? fmt::format("'\\{}'", e) : fmt::format("'\\' before byte 0x{:02x}", u);
        sink_.report(core::DiagnosticKind::InvalidEscape, span(pos_, pos_ + 2),
                     fmt::format("unknown escape {} in string; use \\\", \\\\, \\n or \\t", shown));
      }
      pos_ += 2;
      continue;
    }
    ++pos_;
  }
  sink_.report(core::DiagnosticKind::UnterminatedString, span(begin, begin + 1),
               "string is not closed before the end of the line");
  Token t = make(TokenKind::String, begin);
  t.malformed = true;
  return t;
}

Token Lexer::lex_word(std::size_t begin) {
  while (pos_ < text_.size() && is_ident_char(text_[pos_])) ++pos_;
  Token t = make(TokenKind::Identifier, begin);
  for (const auto& [word, kind] : kKeywords) {
    if (t.text == word) {
      t.kind = kind;
      return t;
    }
  }
  check_length(t);
  return t;
}

Token Lexer::next() {
  for (;;) {
    skip_trivia();
    std::size_t begin = pos_;
    if (pos_ >= text_.size()) return make(TokenKind::EndOfFile, begin);
    char c = text_[pos_];
    if (is_ident_start(c)) return lex_word(begin);
    if (is_digit(c) || (c == '-' && pos_ + 1 < text_.size() && is_digit(text_[pos_ + 1]))) {
      return lex_number(begin);
    }
    if (c == '"') return lex_string(begin);
    ++pos_;
    switch (c) {
      case '{': return make(TokenKind::LBrace, begin);
      case '}': return make(TokenKind::RBrace, begin);
      case '(': return make(TokenKind::LParen, begin);
      case ')': return make(TokenKind::RParen, begin);
      case ',': return make(TokenKind::Comma, begin);
      case ';': return make(TokenKind::Semicolon, begin);
      case '=': return make(TokenKind::Equals, begin);
      case '*': return make(TokenKind::Star, begin);
      default: break;
    }
    // Skip a run of bad bytes with one diagnostic, so binary input does not
    // flood the sink.
    while (pos_ < text_.size()) {
      char d = text_[pos_];
      if (is_ident_start(d) || is_digit(d) || d == '"' || d == '{' || d == '}' || d == '(' || d == ')' || d == ',' ||
          d == ';' || d == '=' || d == '*' || d == '/' || std::isspace(static_cast<unsigned char>(d))) {
        break;
      }
      ++pos_;
    }
    sink_.report(core::DiagnosticKind::InvalidCharacter, span(begin, pos_),
                 fmt::format("unexpected {} in mission text", describe_byte(c)));
  }
}

std::string escape(std::string_view value) {
  std::string out = "\"";
  for (char c : value) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      default: out.push_back(c);
    }
  }
  return out + "\"";
}

std::string unescape(std::string_view quoted) {
  std::string_view body = quoted;
  if (!body.empty() && body.front() == '"') body.remove_prefix(1);
  if (!body.empty() && body.back() == '"') body.remove_suffix(1);
  std::string out;
  out.reserve(body.size());
  for (std::size_t i = 0; i < body.size(); ++i) {
    if (body[i] == '\\' && i + 1 < body.size()) {
      char e = body[++i];
      out.push_back(e == 'n' ? '\n' : e == 't' ? '\t' : e);
    } else {
      out.push_back(body[i]);
    }
  }
  return out;
}

}  // namespace strata::coral
