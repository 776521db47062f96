// The scan of a rule file before SWI-Prolog's reader sees it
// (prolog_rules_scan.h).
#include "strategic/prolog_rules_scan.h"

#include <cctype>
#include <utility>

#include <fmt/format.h>

namespace strata::strategic {

// What SWI-Prolog's reader should not be given. It parses nested brackets
// by C recursion (about 20,000 levels overran the C stack before the engine
// kept its SIGSEGV guard, engine.cpp), and very long lines make the reader
// and the compiler slow (a 1 MB integer, 300,000 chained operators). A file
// over LoadLimits::max_bytes, or not a regular file, is not read at all.
//
// And SWI-Prolog 9.0.4's reader reads freed memory on a digit followed by a
// quote (`0'c`, `16'FF`): raw_read2() keeps a pointer to the digits, adds a
// byte to its buffer, which may move it, and then atoi()s the old place
// (found by prolog_fuzz; fuzz/known/swi_9_0_4_reader_use_after_free.pl).
// Whether it moves depends on the clause's length in the reader's own
// encoding, so any digit followed by a quote outside quoted text and
// comments is refused. So are the two things where the reader's idea of
// quoted text and comments is not this scanner's: `||` (a quasi-quotation,
// read raw to `|}`) and `/*` right after a symbol character (`=/*` is an
// operator there, not a comment).
namespace {

constexpr std::size_t kMaxNesting = 1000;
constexpr std::size_t kMaxLine = 100'000;

bool is_symbol_char(char c) { return std::string_view("#$&*+-./:<=>?@^~\\").find(c) != std::string_view::npos; }

}  // namespace

std::optional<RulesScanProblem> scan_rules_text(std::string_view text) {
  std::size_t line = 1, depth = 0, line_start = 0;
  char prev = ' ';  // the code character before this one (' ' after a comment)
  auto place = [&](std::size_t at, std::string what) {
    return RulesScanProblem{line, at - line_start + 1, std::move(what)};
  };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
      line_start = i + 1;
      prev = ' ';
      continue;
    }
    if (i - line_start >= kMaxLine) {
      return RulesScanProblem{line, 1,
                              fmt::format("a line longer than {} characters: rules are not read past it", kMaxLine)};
    }
    if (c == '%') {  // a comment to the end of the line
      while (i + 1 < text.size() && text[i + 1] != '\n') ++i;
      prev = ' ';
      continue;
    }
    if (c == '/' && i + 1 < text.size() && text[i + 1] == '*') {
      if (is_symbol_char(prev)) {
        return place(i,
                     "`/*` right after a symbol character (the reader takes it as an operator, "
                     "not a comment): put a space before it");
      }
      for (i += 2; i + 1 < text.size() && !(text[i] == '*' && text[i + 1] == '/'); ++i) {
        if (text[i] == '\n') {
          ++line;
          line_start = i + 1;
        }
      }
      ++i;
      prev = ' ';
      continue;
    }
    if (c == '\'' && std::isdigit(static_cast<unsigned char>(prev))) {
      return place(i - 1,
                   "a digit followed by a quote (a character code such as 0'a, or a number "
                   "in a base such as 16'FF): SWI-Prolog 9.0.4's reader can read freed "
                   "memory on it, so rules may not use it; write the number (0'a is 97)");
    }
    if (c == '|' && prev == '|') {
      return place(i - 1, "`||` (a quasi-quotation, which the reader takes raw): not allowed in rules");
    }
    if (c == '\'' || c == '"' || c == '`') {
      for (++i; i < text.size() && text[i] != c; ++i) {
        if (text[i] == '\\' && i + 1 < text.size()) ++i;  // an escape, or a line continued
        if (text[i] == '\n') {
          ++line;
          line_start = i + 1;
        }
      }
      prev = c;
      continue;
    }
    if (c == '(' || c == '[' || c == '{') {
      if (++depth > kMaxNesting) {
        return place(i, fmt::format("a term nested deeper than {} levels: rules are not read past it", kMaxNesting));
      }
    } else if ((c == ')' || c == ']' || c == '}') && depth > 0) {
      --depth;
    }
    prev = c;
  }
  return std::nullopt;
}

}  // namespace strata::strategic
