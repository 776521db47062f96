#include "strategic/coral_catalogue.h"

#include <charconv>
#include <limits>
#include <map>
#include <memory>
#include <string>

namespace strata::strategic {

coral::CheckOptions coral_check_options(const tactical::Catalogue& catalogue, tactical::ExecutionLevel level) {
  using Signatures = std::map<std::string, coral::PrimitiveSignature, std::less<>>;
  auto signatures = std::make_shared<Signatures>();
  coral::CheckOptions options;
  options.execution_level = tactical::execution_level_name(level);
  for (const auto& p : catalogue.all()) {
    coral::PrimitiveSignature sig{p.kind, p.min_args(), p.max_args(), {}, tactical::unavailable_on(level, p)};
    for (const auto& a : p.args) {
      sig.args.push_back({a.name, a.type == tactical::Value::Type::Number, a.unit, a.min, a.max});
    }
    signatures->emplace(p.name, std::move(sig));
    options.primitive_names.push_back(p.name);
  }
  options.primitive = [signatures = std::shared_ptr<const Signatures>(std::move(signatures))](
                          std::string_view name) -> std::optional<coral::PrimitiveSignature> {
    auto it = signatures->find(name);
    if (it == signatures->end()) return std::nullopt;
    return it->second;
  };
  return options;
}

tactical::Value value_of(const coral::ast::Literal& literal) {
  if (literal.kind == coral::ast::Literal::Kind::String) return tactical::Value::of(literal.value);
  double n = 0;
  const char* first = literal.value.data();
  const char* last = first + literal.value.size();
  if (!literal.value.empty() && *first == '+') ++first;  // from_chars takes no '+'
  auto [end, ec] = std::from_chars(first, last, n);
  if (ec != std::errc() || end != last) n = std::numeric_limits<double>::quiet_NaN();
  return tactical::Value::of(n);
}

}  // namespace strata::strategic
