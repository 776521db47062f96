#pragma once
// Internal to strata_vehicle_model: small helpers over toml++ shared by the
// params and scenario loaders, so both report problems the same way:
//   path:line:col: message
// Not installed, not included by public headers.
#include <string>
#include <string_view>

#include <toml++/toml.h>

#include "core/result.h"

namespace strata::vehicle::detail {

// "path:line:col: message" for a node or key (toml::source_region).
core::Error error_at(std::string_view path, const toml::source_region& where,
                     std::string_view message);
// "path: message", for problems that have no place in the text (a missing key).
core::Error error_in(std::string_view path, std::string_view message);

// Parses text (toml::parse) and turns a toml::parse_error into core::Error
// with the parser's line:col. Never throws.
core::Result<toml::table> parse_toml(std::string_view text, std::string_view path);
// Reads and parses a file; a file that cannot be opened is ErrorCode::Io.
core::Result<toml::table> parse_toml_file(std::string_view path);

// The value of a node that must be a number (TOML integer or float).
core::Result<double> number_at(std::string_view path, const toml::node& node,
                               std::string_view what);

}  // namespace strata::vehicle::detail
