#pragma once
// Small text helpers shared by the console, the logs and the CLI.
#include <string>
#include <optional>
#include <string_view>
#include <vector>

namespace strata::core {

// text cut to at most max_bytes bytes (never inside a UTF-8 character),
// followed by ellipsis when it was cut.
std::string shorten(std::string text, std::size_t max_bytes, std::string_view ellipsis);

// Whether text is well-formed UTF-8 (no overlong forms, no surrogates,
// nothing past U+10FFFF).
bool valid_utf8(std::string_view text);

// The closest candidate to `name` by edit distance, if close enough to be a
// plausible typo ("did you mean ...?"): about a third of the name in edits.
std::optional<std::string> suggest(std::string_view name, const std::vector<std::string>& candidates);

}  // namespace strata::core
