#pragma once
#include <cstdint>
#include <string_view>

#include "core/source.h"

namespace strata::coral {

enum class TokenKind : std::uint8_t {
  Identifier,
  Integer,
  Float,
  String,
  LBrace,
  RBrace,
  LParen,
  RParen,
  Comma,
  Semicolon,
  Equals,
  Star,
  KwNet,
  KwMission,
  KwPlace,
  KwExit,
  KwTransition,
  KwPriority,
  KwWait,
  KwAction,
  KwSignal,
  KwData,
  KwImport,
  KwTactic,
  KwPhase,
  KwGuard,
  EndOfFile,
};

std::string_view token_kind_name(TokenKind kind);

struct Token {
  TokenKind kind = TokenKind::EndOfFile;
  core::SourceSpan span;
  std::string_view text;   // the token as written (strings: with quotes)
  bool malformed = false;  // the lexer reported this token already
};

}  // namespace strata::coral
