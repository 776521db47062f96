#include "tactical/catalogue.h"

#include <cctype>

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace strata::tactical {

namespace {

std::string join_names(const std::vector<std::string>& names) { return fmt::format("{}", fmt::join(names, ", ")); }

}  // namespace

std::size_t Primitive::min_args() const {
  std::size_t n = 0;
  for (const auto& a : args) {
    if (!a.default_value) ++n;
  }
  return n;
}

const Argument* Primitive::find_arg(std::string_view arg_name) const {
  for (const auto& a : args) {
    if (a.name == arg_name) return &a;
  }
  return nullptr;
}

std::string Primitive::prolog_predicate() const {
  // The PROLOG rules pass a result variable last (Figure 10: exec_sleep(1,X)).
  switch (kind) {
    case Kind::Exec: return fmt::format("exec_{}/{}", name, args.size() + 1);
    case Kind::Ask: return fmt::format("ask_{}/{}", name, args.size() + 1);
    case Kind::Ood: return fmt::format("ood/{}", args.size() + 2);  // ood('name', ..., X)
    case Kind::Report: return fmt::format("{}/{}", name, args.size());
  }
  return name;
}

std::string Primitive::prolog_call() const {
  std::vector<std::string> params;
  if (kind == Kind::Ood) params.push_back(fmt::format("'{}'", name));
  for (const auto& a : args) {
    std::string var = a.name;
    var[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(var[0])));
    if (var[0] == '_') var.insert(0, "A");  // a PROLOG variable starts with a capital
    params.push_back(std::move(var));
  }
  if (kind != Kind::Report) params.emplace_back("X");
  std::string head;
  switch (kind) {
    case Kind::Exec: head = "exec_" + name; break;
    case Kind::Ask: head = "ask_" + name; break;
    case Kind::Ood: head = "ood"; break;
    case Kind::Report: head = name; break;
  }
  return fmt::format("{}({})", head, join_names(params));
}

}  // namespace strata::tactical
