#pragma once
// Reading TOML files (the primitive catalogue, mission data, the vehicle's
// parameters and scenarios) with every problem located the same way:
//   path:line:col: message
// or "path: message" for a problem with no place in the text (a missing key).
// The library strata_toml (this folder) holds it, so that only the readers of
// TOML link toml++.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

#include "core/result.h"

namespace strata::core {

// The largest TOML file read (parameters, scenarios, catalogues, mission
// data are a few kilobytes).
inline constexpr std::size_t kMaxTomlFileBytes = std::size_t{16} << 20;

// "path:line:col: message", or "path: message" where the region has no line.
std::string toml_located(std::string_view path, const toml::source_region& where, std::string_view message);
// That text as an InvalidInput error.
Error toml_error_at(std::string_view path, const toml::source_region& where, std::string_view message);
// "path: message" as an InvalidInput error.
Error toml_error_in(std::string_view path, std::string_view message);

// Collects located errors while a document is checked, so that one load
// reports every problem it finds, in file order (at most kMaxErrors, then a
// count of the rest).
class TomlErrors {
 public:
  static constexpr std::size_t kMaxErrors = 20;

  explicit TomlErrors(std::string path) : path_(std::move(path)) {}

  void add(const toml::source_region& where, std::string message);
  void add(const toml::node& node, std::string message) { add(node.source(), std::move(message)); }
  void add(const toml::key& key, std::string message) { add(key.source(), std::move(message)); }

  bool empty() const { return entries_.empty(); }
  // All errors, sorted by position, one per line. Code InvalidInput.
  Error error() const;

 private:
  struct Entry {
    toml::source_region where;
    std::string text;
  };
  std::string path_;
  std::vector<Entry> entries_;
  std::size_t dropped_ = 0;
};

// Parses text as TOML; a syntax error becomes "path:line:col: message"
// (InvalidInput). Never throws.
Result<toml::table> parse_toml(std::string_view text, std::string_view path);
// The text of the TOML file at path (core::read_regular_file: a FIFO or a
// device is refused, a file over kMaxTomlFileBytes too); a file that cannot
// be read is an Io error, distinct from a syntax error in a file that exists.
Result<std::string> read_toml_text(const std::string& path);
// read_toml_text, then parse_toml.
Result<toml::table> parse_toml_file(const std::string& path);

// A TOML integer or float as a double; nullopt for any other type.
std::optional<double> toml_number(const toml::node& node);
// The same, or "path:line:col: 'what' must be a number".
Result<double> toml_number_at(std::string_view path, const toml::node& node, std::string_view what);

// "a string", "an integer", "a table", ... for messages.
std::string_view toml_type_phrase(const toml::node& node);

}  // namespace strata::core
