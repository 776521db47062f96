#pragma once
// Internal to strata_coral: the parser's token plumbing. A cursor over the
// lexer's tokens that reports syntax errors once per panic (a cascade after
// the first error is suppressed until the parser resumes at a declaration),
// recovers by skipping to a closer at nesting depth 0, and reads the small
// things every rule needs (names, bounded integers, priorities, literals).
// The grammar itself is the parser's (parser.cpp).
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "coral/ast.h"
#include "coral/lexer.h"
#include "core/diagnostic.h"

namespace strata::coral {

// Tokens that start a declaration: recovery never skips past one.
bool is_declaration_keyword(TokenKind k);
bool is_clause_keyword(TokenKind k);
// A token for messages: its text (cut at 40 bytes) for names and numbers,
// "a string", or its kind's name.
std::string describe(const Token& t);

class TokenCursor {
 protected:
  // Reads the first token.
  TokenCursor(core::FileId id, std::string_view text, core::DiagnosticSink& sink);

  void advance();
  bool at(TokenKind k) const { return tok_.kind == k; }
  bool match(TokenKind k);
  // An UnexpectedToken error at t, unless in a panic already (or the lexer
  // rejected t and said why); starts a panic.
  void error_at(const Token& t, const std::string& message);
  void error_here(const std::string& expected);
  bool expect(TokenKind k, std::string_view context);

  // Skips to `closer` at nesting depth 0 and consumes it (returns true), or
  // stops before a declaration keyword (or a clause keyword, if
  // `stop_at_clause`) or an enclosing block's '}' so the enclosing loop can
  // resume there (returns false).
  bool recover(TokenKind closer, bool stop_at_clause = false);

  // The span from the start of a to the end of b.
  static core::SourceSpan join(core::SourceSpan a, core::SourceSpan b);

  std::optional<ast::Name> name(std::string_view what);
  // An unsigned integer in [lo, hi]; out of range gives `kind` and returns lo.
  std::uint32_t integer(std::uint64_t lo, std::uint64_t hi, core::DiagnosticKind kind, std::string_view what,
                        core::SourceSpan* where = nullptr);
  // A priority in [-kMaxPriority, kMaxPriority]; out of range gives InvalidNumber and 0.
  int priority();
  // The current string, float or integer token as a literal.
  ast::Literal literal();

  Lexer lexer_;
  core::DiagnosticSink& sink_;
  Token tok_;
  Token prev_;
  bool panic_ = false;
};

}  // namespace strata::coral
