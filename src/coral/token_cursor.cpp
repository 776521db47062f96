#include "coral/token_cursor.h"

#include <charconv>

#include <fmt/format.h>

namespace strata::coral {

using core::DiagnosticKind;
using TK = TokenKind;

bool is_declaration_keyword(TK k) {
  return k == TK::KwNet || k == TK::KwMission || k == TK::KwImport || k == TK::KwPlace || k == TK::KwExit ||
         k == TK::KwData || k == TK::KwTransition || k == TK::KwGuard;
}

bool is_clause_keyword(TK k) { return k == TK::KwWait || k == TK::KwAction || k == TK::KwSignal; }

std::string describe(const Token& t) {
  switch (t.kind) {
    case TK::Identifier:
    case TK::Integer:
    case TK::Float: return fmt::format("'{}'", t.text.substr(0, 40));
    case TK::String: return "a string";
    default: return std::string(token_kind_name(t.kind));
  }
}

TokenCursor::TokenCursor(core::FileId id, std::string_view text, core::DiagnosticSink& sink)
    : lexer_(id, text, sink), sink_(sink) {
  advance();
}

void TokenCursor::advance() {
  prev_ = tok_;
  tok_ = lexer_.next();
  // After a token the lexer rejected, syntax errors until the next
  // declaration would only echo it.
  if (tok_.malformed) panic_ = true;
}
bool TokenCursor::match(TK k) {
  if (!at(k)) return false;
  advance();
  return true;
}
void TokenCursor::error_at(const Token& t, const std::string& message) {
  if (panic_) return;
  panic_ = true;
  if (t.malformed) return;  // the lexer said what is wrong with it
  sink_.report(DiagnosticKind::UnexpectedToken, t.span, message);
}
void TokenCursor::error_here(const std::string& expected) {
  error_at(tok_, fmt::format("{}, found {}", expected, describe(tok_)));
}
bool TokenCursor::expect(TK k, std::string_view context) {
  if (match(k)) return true;
  error_here(fmt::format("expected {} {}", token_kind_name(k), context));
  return false;
}

bool TokenCursor::recover(TK closer, bool stop_at_clause) {
  int depth = 0;
  while (!at(TK::EndOfFile)) {
    if (depth == 0 && at(closer)) {
      advance();
      return true;
    }
    if (depth == 0 && (is_declaration_keyword(tok_.kind) || (stop_at_clause && is_clause_keyword(tok_.kind)))) {
      return false;
    }
    if (at(TK::LBrace) || at(TK::LParen)) {
      ++depth;
    } else if ((at(TK::RBrace) || at(TK::RParen)) && depth > 0) {
      --depth;
    } else if (at(TK::RBrace)) {
      return false;  // the end of an enclosing block
    }
    advance();
  }
  return false;
}

core::SourceSpan TokenCursor::join(core::SourceSpan a, core::SourceSpan b) {
  return {a.file, a.offset, b.offset + b.length - a.offset};
}

std::optional<ast::Name> TokenCursor::name(std::string_view what) {
  if (!at(TK::Identifier)) {
    error_here(fmt::format("expected {}", what));
    return std::nullopt;
  }
  ast::Name n{std::string(tok_.text), tok_.span};
  advance();
  return n;
}

std::uint32_t TokenCursor::integer(std::uint64_t lo, std::uint64_t hi, DiagnosticKind kind, std::string_view what,
                                   core::SourceSpan* where) {
  if (!at(TK::Integer)) {
    error_here(fmt::format("expected {}", what));
    return static_cast<std::uint32_t>(lo);
  }
  std::uint64_t v = 0;
  auto [p, ec] = std::from_chars(tok_.text.data(), tok_.text.data() + tok_.text.size(), v);
  bool ok = ec == std::errc() && p == tok_.text.data() + tok_.text.size() && v >= lo && v <= hi;
  if (where) *where = tok_.span;
  if (!ok) {
    sink_.report(kind, tok_.span,
                 fmt::format("{} must be from {} to {}, not {}", what, lo, hi, tok_.text.substr(0, 40)));
    v = lo;
  }
  advance();
  return static_cast<std::uint32_t>(v);
}

int TokenCursor::priority() {
  constexpr long long kMaxPriority = 1000000;
  if (!at(TK::Integer)) {
    error_here("expected a priority (an integer)");
    return 0;
  }
  long long v = 0;
  auto [p, ec] = std::from_chars(tok_.text.data(), tok_.text.data() + tok_.text.size(), v);
  bool ok = ec == std::errc() && p == tok_.text.data() + tok_.text.size() && v >= -kMaxPriority && v <= kMaxPriority;
  if (!ok) {
    sink_.report(
        DiagnosticKind::InvalidNumber, tok_.span,
        fmt::format("a priority must be from {} to {}, not {}", -kMaxPriority, kMaxPriority, tok_.text.substr(0, 40)));
    v = 0;
  }
  advance();
  return static_cast<int>(v);
}

ast::Literal TokenCursor::literal() {
  ast::Literal lit;
  lit.kind = at(TK::String)  ? ast::Literal::Kind::String
             : at(TK::Float) ? ast::Literal::Kind::Float
                             : ast::Literal::Kind::Integer;
  lit.text = std::string(tok_.text);
  lit.value = lit.kind == ast::Literal::Kind::String ? unescape(tok_.text) : lit.text;
  lit.span = tok_.span;
  advance();
  return lit;
}

}  // namespace strata::coral
