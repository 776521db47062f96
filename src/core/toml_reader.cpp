#include "core/toml_reader.h"

#include <algorithm>

#include <fmt/format.h>

#include "core/file.h"

namespace strata::core {

std::string toml_located(std::string_view path, const toml::source_region& where, std::string_view message) {
  if (where.begin.line == 0) return fmt::format("{}: {}", path, message);
  return fmt::format("{}:{}:{}: {}", path, where.begin.line, where.begin.column, message);
}

Error toml_error_at(std::string_view path, const toml::source_region& where, std::string_view message) {
  return make_error(ErrorCode::InvalidInput, toml_located(path, where, message));
}

Error toml_error_in(std::string_view path, std::string_view message) {
  return make_error(ErrorCode::InvalidInput, fmt::format("{}: {}", path, message));
}

void TomlErrors::add(const toml::source_region& where, std::string message) {
  if (entries_.size() >= kMaxErrors) {
    ++dropped_;
    return;
  }
  entries_.push_back({where, std::move(message)});
}

Error TomlErrors::error() const {
  std::vector<const Entry*> sorted;
  for (const auto& e : entries_) sorted.push_back(&e);
  std::stable_sort(sorted.begin(), sorted.end(), [](const Entry* a, const Entry* b) {
    const auto& x = a->where.begin;
    const auto& y = b->where.begin;
    return x.line != y.line ? x.line < y.line : x.column < y.column;
  });
  std::string out;
  for (const Entry* e : sorted) {
    if (!out.empty()) out += '\n';
    out += toml_located(path_, e->where, e->text);
  }
  if (dropped_ > 0) out += fmt::format("\n{}: {} more error(s) not shown", path_, dropped_);
  return make_error(ErrorCode::InvalidInput, std::move(out));
}

Result<toml::table> parse_toml(std::string_view text, std::string_view path) {
  try {
    return toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    return toml_error_at(path, e.source(), e.description());
  }
}

Result<std::string> read_toml_text(const std::string& path) {
  return read_regular_file(path, kMaxTomlFileBytes, [](const std::string& p, const char* reason) {
    return p + ": cannot open file: " + reason;
  });
}

Result<toml::table> parse_toml_file(const std::string& path) {
  auto text = read_toml_text(path);
  if (!text) return text.error();
  return parse_toml(text.value(), path);
}

std::optional<double> toml_number(const toml::node& node) {
  if (const auto* i = node.as_integer()) return static_cast<double>(i->get());
  if (const auto* f = node.as_floating_point()) return f->get();
  return std::nullopt;
}

Result<double> toml_number_at(std::string_view path, const toml::node& node, std::string_view what) {
  if (auto v = toml_number(node)) return *v;
  return toml_error_at(path, node.source(), fmt::format("'{}' must be a number", what));
}

std::string_view toml_type_phrase(const toml::node& node) {
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

}  // namespace strata::core
