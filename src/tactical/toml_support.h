#pragma once
// Internal to strata_tactical: reading TOML files (the primitive catalogue, the
// mission data) with every problem located as "path:line:col: message".
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

#include "core/result.h"

namespace strata::tactical::detail {

// Collects located errors while a document is checked, so that one load
// reports every problem it finds, in file order.
class TomlErrors {
 public:
  static constexpr std::size_t kMaxErrors = 20;

  explicit TomlErrors(std::string path) : path_(std::move(path)) {}

  void add(const toml::source_region& where, std::string message);
  void add(const toml::node& node, std::string message) { add(node.source(), std::move(message)); }
  void add(const toml::key& key, std::string message) { add(key.source(), std::move(message)); }

  bool empty() const { return entries_.empty(); }
  // All errors, sorted by position, one per line. Code InvalidInput.
  core::Error error() const;

 private:
  struct Entry {
    std::uint32_t line = 0;
    std::uint32_t col = 0;
    std::string text;
  };
  std::string path_;
  std::vector<Entry> entries_;
  std::size_t dropped_ = 0;
};

// Parses text as TOML; a syntax error becomes "path:line:col: message".
core::Result<toml::table> parse_toml(std::string_view text, const std::string& path);

// The whole file, or an Io error naming path.
core::Result<std::string> read_text_file(const std::string& path);

// A TOML integer or float as a double; nullopt for any other type.
std::optional<double> as_number(const toml::node& node);

// "a string", "an integer", "a table", ... for messages.
std::string_view type_phrase(const toml::node& node);

}  // namespace strata::tactical::detail
