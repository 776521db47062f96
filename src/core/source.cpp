#include "core/source.h"

#include <algorithm>

namespace strata::core {

FileId SourceManager::add(std::string path, std::string text) {
  File f{std::move(path), std::move(text), {0}};
  for (std::uint32_t i = 0; i < f.text.size(); ++i) {
    if (f.text[i] == '\n') f.line_starts.push_back(i + 1);
  }
  files_.push_back(std::move(f));
  return static_cast<FileId>(files_.size() - 1);
}

LineCol SourceManager::line_col(FileId id, std::uint32_t offset) const {
  const File& f = files_.at(id);
  auto it = std::upper_bound(f.line_starts.begin(), f.line_starts.end(), offset);
  auto line = static_cast<std::uint32_t>(it - f.line_starts.begin());  // >= 1
  return {line, offset - f.line_starts[line - 1] + 1};
}

std::uint32_t SourceManager::offset_of(FileId id, LineCol at) const {
  const File& f = files_.at(id);
  const std::uint32_t line = std::clamp<std::uint32_t>(at.line, 1, static_cast<std::uint32_t>(f.line_starts.size()));
  const std::uint32_t begin = f.line_starts[line - 1];
  const auto length = static_cast<std::uint32_t>(line_text(id, line).size());
  return begin + std::min(at.col > 0 ? at.col - 1 : 0, length);
}

std::string_view SourceManager::line_text(FileId id, std::uint32_t line) const {
  const File& f = files_.at(id);
  if (line == 0 || line > f.line_starts.size()) return {};
  std::uint32_t begin = f.line_starts[line - 1];
  std::uint32_t end = line < f.line_starts.size() ? f.line_starts[line] - 1 : static_cast<std::uint32_t>(f.text.size());
  std::string_view s(f.text.data() + begin, end - begin);
  if (!s.empty() && s.back() == '\r') s.remove_suffix(1);
  return s;
}

}  // namespace strata::core
