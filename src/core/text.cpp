#include "core/text.h"

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

}  // namespace strata::core
