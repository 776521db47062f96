#pragma once
// Turns CORAL source into tokens on demand. Lexical errors become
// diagnostics; the lexer then skips the bad bytes and goes on, so the parser
// always sees a well-formed token stream ending in EndOfFile.
#include <string>
#include <string_view>

#include "coral/token.h"
#include "core/diagnostic.h"

namespace strata::coral {

inline constexpr std::size_t kMaxTokenLength = 4096;                          // bytes
inline constexpr std::size_t kMaxSourceSize = std::size_t{16} * 1024 * 1024;  // bytes

class Lexer {
 public:
  // text must outlive the lexer and every token it returns.
  Lexer(core::FileId file, std::string_view text, core::DiagnosticSink& sink);

  Token next();

 private:
  Token make(TokenKind kind, std::size_t begin) const;
  core::SourceSpan span(std::size_t begin, std::size_t end) const;
  void skip_trivia();
  Token lex_number(std::size_t begin);
  Token lex_string(std::size_t begin);
  Token lex_word(std::size_t begin);
  void check_length(const Token& t);

  core::FileId file_;
  std::string_view text_;
  core::DiagnosticSink& sink_;
  std::size_t pos_ = 0;
};

// The value of a string literal token (quotes removed, escapes applied).
// Assumes the lexer already reported any malformed escape.
std::string unescape(std::string_view quoted);
// The inverse: a quoted literal whose unescape() is value.
std::string escape(std::string_view value);

}  // namespace strata::coral
