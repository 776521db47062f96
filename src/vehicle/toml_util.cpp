#include "vehicle/toml_util.h"

#include <fstream>
#include <sstream>

#include <fmt/format.h>

namespace strata::vehicle::detail {

core::Error error_at(std::string_view path, const toml::source_region& where,
                     std::string_view message) {
  return core::make_error(core::ErrorCode::InvalidInput,
                          fmt::format("{}:{}:{}: {}", path, where.begin.line, where.begin.column,
                                      message));
}

core::Error error_in(std::string_view path, std::string_view message) {
  return core::make_error(core::ErrorCode::InvalidInput, fmt::format("{}: {}", path, message));
}

core::Result<toml::table> parse_toml(std::string_view text, std::string_view path) {
  try {
    return toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    return error_at(path, e.source(), e.description());
  }
}

core::Result<toml::table> parse_toml_file(std::string_view path) {
  // Read the file ourselves so a missing file is an I/O error, distinct from
  // a syntax error in a file that exists.
  std::ifstream in{std::string(path), std::ios::binary};
  if (!in) {
    return core::make_error(core::ErrorCode::Io, fmt::format("{}: cannot open file", path));
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) {
    return core::make_error(core::ErrorCode::Io, fmt::format("{}: cannot read file", path));
  }
  return parse_toml(text.str(), path);
}

core::Result<double> number_at(std::string_view path, const toml::node& node,
                               std::string_view what) {
  if (!node.is_number()) {
    return error_at(path, node.source(), fmt::format("'{}' must be a number", what));
  }
  return *node.value<double>();
}

}  // namespace strata::vehicle::detail
