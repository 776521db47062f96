#pragma once
// The scan of a PROLOG rule file before SWI-Prolog's reader is given it
// (docs/prolog.md, section 7): what the reader must not see, with its
// place. Quoted text and comments are skipped.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace strata::strategic {

struct RulesScanProblem {
  std::size_t line = 0;    // from 1
  std::size_t column = 0;  // from 1, in bytes
  std::string text;
};

// The first problem in Prolog text, or nullopt: a term nested deeper than
// 1000 brackets, a line over 100,000 characters, a digit followed by a
// quote (SWI-Prolog 9.0.4's reader bug), `||`, and `/*` right after a
// symbol character.
std::optional<RulesScanProblem> scan_rules_text(std::string_view text);

}  // namespace strata::strategic
