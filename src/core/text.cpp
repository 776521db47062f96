#include "core/text.h"

#include <algorithm>
#include <cstdint>

namespace strata::core {

std::string shorten(std::string text, std::size_t max_bytes, std::string_view ellipsis) {
  if (text.size() <= max_bytes) return text;
  std::size_t cut = max_bytes;
  // A UTF-8 continuation byte (10xxxxxx) would split a character: back up.
  while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) --cut;
  text.resize(cut);
  text.append(ellipsis);
  return text;
}

bool valid_utf8(std::string_view text) {
  std::size_t i = 0;
  while (i < text.size()) {
    const auto c = static_cast<unsigned char>(text[i]);
    std::size_t n = 0;
    std::uint32_t cp = 0;
    if (c < 0x80) {
      ++i;
      continue;
    } else if (c >= 0xC2 && c <= 0xDF) {
      n = 1;
      cp = c & 0x1Fu;
    } else if (c >= 0xE0 && c <= 0xEF) {
      n = 2;
      cp = c & 0x0Fu;
    } else if (c >= 0xF0 && c <= 0xF4) {
      n = 3;
      cp = c & 0x07u;
    } else {
      return false;
    }
    for (std::size_t k = 1; k <= n; ++k) {
      if (i + k >= text.size()) return false;
      const auto d = static_cast<unsigned char>(text[i + k]);
      if ((d & 0xC0u) != 0x80u) return false;
      cp = (cp << 6) | (d & 0x3Fu);
    }
    if ((n == 2 && cp < 0x800) || (n == 3 && (cp < 0x10000 || cp > 0x10FFFF)) || (cp >= 0xD800 && cp <= 0xDFFF)) {
      return false;
    }
    i += n + 1;
  }
  return true;
}

std::optional<std::string> suggest(std::string_view name, const std::vector<std::string>& candidates) {
  // Edits and swaps of two neighbours ("rnu" is one swap from "run"): the
  // optimal string alignment distance, three rows.
  auto distance = [](std::string_view a, std::string_view b) {
    std::vector<std::size_t> before(b.size() + 1), prev(b.size() + 1), row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
      row[0] = i;
      for (std::size_t j = 1; j <= b.size(); ++j) {
        row[j] = std::min({prev[j] + 1, row[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
        if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
          row[j] = std::min(row[j], before[j - 2] + 1);
      }
      std::swap(before, prev);
      std::swap(prev, row);
    }
    return prev[b.size()];
  };
  if (name.size() > 64) return std::nullopt;
  std::optional<std::string> best;
  // Accept up to about a third of the name in edits (two for a five-letter name).
  std::size_t best_d = std::max<std::size_t>(1, (name.size() + 2) / 3) + 1;
  // Bound the work on huge nets: at most kMaxTried distance computations.
  constexpr std::size_t kMaxTried = 4096;
  std::size_t tried = 0;
  for (const auto& c : candidates) {
    std::size_t gap = c.size() > name.size() ? c.size() - name.size() : name.size() - c.size();
    if (c.size() > 64 || gap >= best_d) continue;  // length alone rules it out
    if (++tried > kMaxTried) break;
    std::size_t d = distance(name, c);
    if (d < best_d) {
      best_d = d;
      best = c;
    }
  }
  return best;
}

}  // namespace strata::core
