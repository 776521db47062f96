#pragma once
// Source text kept in memory for the whole of a load, so diagnostics can show
// the offending line. Spans are byte offsets; line and column are computed on
// demand (1-based, columns count bytes).
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace strata::core {

using FileId = std::uint32_t;

struct SourceSpan {
  FileId file = 0;
  std::uint32_t offset = 0;  // byte offset of the first character
  std::uint32_t length = 0;  // bytes; 0 means a point
};

struct LineCol {
  std::uint32_t line = 0;  // 1-based
  std::uint32_t col = 0;   // 1-based, in bytes
};

class SourceManager {
 public:
  // Takes a copy of text; the returned id stays valid for the manager's life.
  FileId add(std::string path, std::string text);

  const std::string& path(FileId id) const { return files_.at(id).path; }
  std::string_view text(FileId id) const { return files_.at(id).text; }
  std::size_t size() const { return files_.size(); }

  LineCol line_col(FileId id, std::uint32_t offset) const;
  // The offset of a 1-based line and column (in bytes), as a tool outside
  // Strata gives them (SWI-Prolog): a column past its line's end is taken
  // as the end, a line past the last as the last.
  std::uint32_t offset_of(FileId id, LineCol at) const;
  // The whole line holding offset, without its line terminator.
  std::string_view line_text(FileId id, std::uint32_t line) const;

 private:
  struct File {
    std::string path;
    std::string text;
    std::vector<std::uint32_t> line_starts;
  };
  std::vector<File> files_;
};

}  // namespace strata::core
