#include "tactical/toml_support.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

namespace strata::tactical::detail {

void TomlErrors::add(const toml::source_region& where, std::string message) {
  if (entries_.size() >= kMaxErrors) {
    ++dropped_;
    return;
  }
  entries_.push_back({where.begin.line, where.begin.column, std::move(message)});
}

core::Error TomlErrors::error() const {
  std::vector<Entry> sorted = entries_;
  std::stable_sort(sorted.begin(), sorted.end(), [](const Entry& a, const Entry& b) {
    return a.line != b.line ? a.line < b.line : a.col < b.col;
  });
  std::string out;
  for (const auto& e : sorted) {
    if (!out.empty()) out += '\n';
    if (e.line == 0) {
      out += fmt::format("{}: {}", path_, e.text);
    } else {
      out += fmt::format("{}:{}:{}: {}", path_, e.line, e.col, e.text);
    }
  }
  if (dropped_ > 0) out += fmt::format("\n{}: {} more error(s) not shown", path_, dropped_);
  return core::make_error(core::ErrorCode::InvalidInput, std::move(out));
}

core::Result<toml::table> parse_toml(std::string_view text, const std::string& path) {
  try {
    return toml::parse(text, std::string_view(path));
  } catch (const toml::parse_error& e) {
    const auto& at = e.source().begin;
    return core::make_error(core::ErrorCode::InvalidInput,
                            fmt::format("{}:{}:{}: {}", path, at.line, at.column, e.description()));
  }
}

core::Result<std::string> read_text_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    return core::make_error(core::ErrorCode::Io,
                            fmt::format("{}: cannot open: {}", path, std::strerror(errno)));
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) return core::make_error(core::ErrorCode::Io, fmt::format("{}: read failed", path));
  return text.str();
}

std::optional<double> as_number(const toml::node& node) {
  if (const auto* i = node.as_integer()) return static_cast<double>(i->get());
  if (const auto* f = node.as_floating_point()) return f->get();
  return std::nullopt;
}

std::string_view type_phrase(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::table: return "a table";
    case toml::node_type::array: return "an array";
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a float";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::date: return "a date";
    case toml::node_type::time: return "a time";
    case toml::node_type::date_time: return "a date-time";
    case toml::node_type::none: break;
  }
  return "nothing";
}

}  // namespace strata::tactical::detail
