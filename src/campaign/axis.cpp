#include "campaign/axis.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace strata::campaign {

std::uint64_t SplitMix64::next() {
  std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

std::uint64_t stable_hash(const std::string& text) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (unsigned char c : text) {
    h ^= c;
    h *= 0x100000001b3ULL;
  }
  return h;
}

namespace {

// Grid points as a person writes them: 0.1 * 3 is 0.3, not 0.30000000000000004.
double tidy(double x) { return std::round(x * 1e9) / 1e9; }

std::string range_text(const AxisRules& r) {
  if (r.min <= -1e300 && r.max >= 1e300) return "a finite number";
  if (r.max >= 1e300) return fmt::format("{} {}", r.zero_allowed ? ">=" : ">", r.min);
  return fmt::format("in [{}, {}]", r.min, r.max);
}

bool in_range(double x, const AxisRules& r) {
  if (!std::isfinite(x) || x < r.min || x > r.max) return false;
  return r.zero_allowed || x != r.min;
}

// A number in range, else an error at the node.
std::optional<double> value_at(core::TomlErrors& errors, const toml::node& node, const AxisRules& r,
                               const std::string& what) {
  auto v = core::toml_number(node);
  if (!v) {
    errors.add(node, fmt::format("'{}' must be a number, not {}", what, core::toml_type_phrase(node)));
    return std::nullopt;
  }
  if (!in_range(*v, r)) {
    errors.add(node, fmt::format("'{}' must be {} (it is {})", what, range_text(r), *v));
    return std::nullopt;
  }
  return v;
}

std::optional<std::vector<double>> parse_table(core::TomlErrors& errors, const toml::table& t, const AxisRules& r,
                                               std::uint64_t sample_seed, const std::string& stream) {
  bool ok = true;
  for (auto&& [key, node] : t) {
    const std::string_view k = key.str();
    if (k != "from" && k != "to" && k != "step" && k != "sampled") {
      errors.add(key, fmt::format("unknown key '{}' in '{}' (expected from, to, and step or sampled)", k, r.what));
      ok = false;
    }
  }
  const toml::node* from_node = t.get("from");
  const toml::node* to_node = t.get("to");
  const toml::node* step_node = t.get("step");
  const toml::node* sampled_node = t.get("sampled");
  if (from_node == nullptr || to_node == nullptr) {
    errors.add(t, fmt::format("'{}' needs 'from' and 'to'", r.what));
    return std::nullopt;
  }
  if ((step_node == nullptr) == (sampled_node == nullptr)) {
    errors.add(t, fmt::format("'{}' needs exactly one of 'step' (a grid) and 'sampled' (a count)", r.what));
    return std::nullopt;
  }
  auto from = value_at(errors, *from_node, r, r.what + ".from");
  auto to = value_at(errors, *to_node, r, r.what + ".to");
  if (!ok || !from || !to) return std::nullopt;
  if (*to < *from) {
    errors.add(*to_node, fmt::format("'{}.to' ({}) is below '{}.from' ({})", r.what, *to, r.what, *from));
    return std::nullopt;
  }
  std::vector<double> values;
  if (step_node != nullptr) {
    auto step = core::toml_number(*step_node);
    if (!step || !std::isfinite(*step) || *step <= 0.0) {
      errors.add(*step_node, fmt::format("'{}.step' must be a number > 0", r.what));
      return std::nullopt;
    }
    // Counted before anything is made: a step of 1e-300 is an error, not an
    // allocation. The small slack keeps `to` itself when (to-from)/step is
    // an integer up to rounding.
    const double span = (*to - *from) / *step;
    if (!(span < static_cast<double>(r.max_values))) {
      errors.add(*step_node, fmt::format("'{}' makes more than {} values (from {} to {} by {})", r.what, r.max_values,
                                         *from, *to, *step));
      return std::nullopt;
    }
    const auto n = static_cast<std::uint64_t>(std::floor(span + 1e-9)) + 1;
    values.reserve(n);
    for (std::uint64_t i = 0; i < n; ++i) values.push_back(std::min(*to, tidy(*from + static_cast<double>(i) * *step)));
    return values;
  }
  const auto* count = sampled_node->as_integer();
  if (count == nullptr || count->get() < 1) {
    errors.add(*sampled_node, fmt::format("'{}.sampled' must be an integer >= 1", r.what));
    return std::nullopt;
  }
  if (static_cast<std::uint64_t>(count->get()) > r.max_values) {
    errors.add(*sampled_node, fmt::format("'{}.sampled' is over the limit of {} values", r.what, r.max_values));
    return std::nullopt;
  }
  SplitMix64 rng(sample_seed ^ stable_hash(stream));
  for (std::int64_t i = 0; i < count->get(); ++i) {
    double x = *from + rng.unit() * (*to - *from);
    // Sampled points are kept to a microsecond (or a millionth): readable,
    // and exact through TOML and JSON.
    x = std::clamp(std::round(x * 1e6) / 1e6, *from, *to);
    if (!r.zero_allowed && x == r.min) x = *to;
    values.push_back(x);
  }
  std::sort(values.begin(), values.end());
  return values;
}

}  // namespace

std::optional<std::vector<double>> parse_axis(core::TomlErrors& errors, const toml::node& node, const AxisRules& r,
                                              std::uint64_t sample_seed, const std::string& stream) {
  if (const toml::table* t = node.as_table()) return parse_table(errors, *t, r, sample_seed, stream);
  if (const toml::array* a = node.as_array()) {
    if (a->empty()) {
      errors.add(node, fmt::format("'{}' must not be an empty list", r.what));
      return std::nullopt;
    }
    if (a->size() > r.max_values) {
      errors.add(node, fmt::format("'{}' has more than {} values", r.what, r.max_values));
      return std::nullopt;
    }
    std::vector<double> values;
    bool ok = true;
    for (const toml::node& item : *a) {
      auto v = value_at(errors, item, r, r.what);
      if (v) values.push_back(*v);
      ok = ok && v.has_value();
    }
    if (!ok) return std::nullopt;
    return values;
  }
  auto v = value_at(errors, node, r, r.what);
  if (!v) return std::nullopt;
  return std::vector<double>{*v};
}

}  // namespace strata::campaign
