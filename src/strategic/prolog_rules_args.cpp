#include "strategic/prolog_rules_args.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <optional>
#include <string>

#include <fmt/format.h>

namespace strata::strategic {
namespace {

bool is_name_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

// A Prolog number as a rule writes it: 400, -1, 0.05, 1.0e3 (a float needs
// digits on both sides of the point).
// (By hand, not std::regex: libstdc++'s recurses per character, and a rule
// line may hold 100,000 digits.)
std::optional<double> literal_number(std::string_view s) {
  auto digits = [&](std::size_t& i) {
    std::size_t from = i;
    while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) ++i;
    return i > from;
  };
  std::size_t i = 0;
  if (i < s.size() && s[i] == '-') ++i;
  if (!digits(i)) return std::nullopt;
  if (i < s.size() && s[i] == '.') {
    ++i;
    if (!digits(i)) return std::nullopt;
  }
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
    if (!digits(i)) return std::nullopt;
  }
  if (i != s.size()) return std::nullopt;
  double n = 0;
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), n);
  if (end != s.data() + s.size()) return std::nullopt;
  if (ec == std::errc::result_out_of_range) return HUGE_VAL;
  return n;
}

std::string with_unit(double n, const std::string& unit) {
  return unit.empty() ? fmt::format("{}", n) : fmt::format("{} {}", n, unit);
}

// Finds the primitive calls of rule text; checks the literal numbers among
// their arguments or, given an Execution level, whether it carries them out.
class Scanner {
 public:
  Scanner(std::string_view text, const tactical::Catalogue& catalogue,
          std::optional<tactical::ExecutionLevel> level = std::nullopt)
      : text_(text), catalogue_(catalogue), level_(level) {}

  std::vector<RulesScanProblem> run() {
    while (i_ < text_.size()) {
      const char c = text_[i_];
      if (skip_layout()) continue;
      if (std::islower(static_cast<unsigned char>(c)) && (i_ == 0 || !is_name_char(text_[i_ - 1]))) {
        std::size_t start = i_;
        while (i_ < text_.size() && is_name_char(text_[i_])) ++i_;
        if (i_ < text_.size() && text_[i_] == '(') {
          const std::string_view name = text_.substr(start, i_ - start);
          if (level_) {
            unavailable(name, start - line_start_ + 1);
          } else {
            call(name);
          }
        }
        continue;
      }
      step();
    }
    return std::move(problems_);
  }

 private:
  // One character, keeping the line count.
  void step() {
    if (text_[i_] == '\n') {
      ++line_;
      line_start_ = i_ + 1;
    }
    ++i_;
  }

  // Skips a comment or quoted text at i_, if there is one there.
  bool skip_layout() {
    const char c = text_[i_];
    if (c == '%') {
      while (i_ < text_.size() && text_[i_] != '\n') ++i_;
      return true;
    }
    if (c == '/' && i_ + 1 < text_.size() && text_[i_ + 1] == '*') {
      i_ += 2;
      while (i_ < text_.size() && !(text_[i_] == '*' && i_ + 1 < text_.size() && text_[i_ + 1] == '/')) step();
      i_ = std::min(text_.size(), i_ + 2);
      return true;
    }
    if (c == '\'' || c == '"' || c == '`') {
      ++i_;
      while (i_ < text_.size() && text_[i_] != c) {
        if (text_[i_] == '\\' && i_ + 1 < text_.size()) step();
        step();
      }
      if (i_ < text_.size()) ++i_;
      return true;
    }
    return false;
  }

  // The primitive that `name(` calls (exec_NAME, ask_NAME, or ood with
  // NAME first), or nullptr. i_ is at the '('.
  const tactical::Primitive* called(std::string_view name) const {
    auto of_kind = [this](std::string_view primitive, tactical::Kind kind) -> const tactical::Primitive* {
      const tactical::Primitive* p = catalogue_.find(primitive);
      return p && p->kind == kind ? p : nullptr;
    };
    if (name.starts_with("exec_")) return of_kind(name.substr(5), tactical::Kind::Exec);
    if (name.starts_with("ask_")) return of_kind(name.substr(4), tactical::Kind::Ask);
    if (name != "ood") return nullptr;
    // ood('start_network', X), or ood(start_network, X)
    std::size_t at = i_ + 1;
    while (at < text_.size() && std::isspace(static_cast<unsigned char>(text_[at]))) ++at;
    const bool quoted = at < text_.size() && text_[at] == '\'';
    if (quoted) ++at;
    const std::size_t from = at;
    while (at < text_.size() && is_name_char(text_[at])) ++at;
    if (at == from || (quoted && (at == text_.size() || text_[at] != '\''))) return nullptr;
    return of_kind(text_.substr(from, at - from), tactical::Kind::Ood);
  }

  // At the '(' after `name`, which starts at `column` of this line: a call
  // of a primitive that *level_ cannot carry out is a problem there.
  void unavailable(std::string_view name, std::size_t column) {
    const tactical::Primitive* p = called(name);
    if (!p) return;
    auto why = tactical::unavailable_on(*level_, *p);
    if (!why) return;
    problems_.push_back(
        {line_, column,
         fmt::format("'{}' is not available on {}: {}", p->name, tactical::execution_level_name(*level_), *why)});
  }

  // At the '(' after `name`: reads the arguments at depth 1 and checks the
  // literal numbers among them. The scan goes on inside the parentheses, so
  // a call nested in another's arguments is checked too.
  void call(std::string_view name) {
    const tactical::Primitive* p = name == "ood" ? nullptr : called(name);
    if (!p || p->args.empty()) return;
    struct Arg {
      std::size_t offset, line, column;
      std::string text;
    };
    std::vector<Arg> args;
    const std::size_t save_i = i_, save_line = line_, save_start = line_start_;
    ++i_;  // '('
    std::size_t depth = 0;
    Arg current{i_, line_, i_ - line_start_ + 1, {}};
    bool closed = false;
    while (i_ < text_.size()) {
      const std::size_t before = i_;
      if (skip_layout()) {
        current.text.append(text_.substr(before, i_ - before));
        continue;
      }
      const char c = text_[i_];
      if (depth == 0 && (c == ',' || c == ')')) {
        args.push_back(std::move(current));
        if (c == ')') {
          closed = true;
          break;
        }
        step();
        current = Arg{i_, line_, i_ - line_start_ + 1, {}};
        continue;
      }
      if (c == '(' || c == '[' || c == '{') ++depth;
      if ((c == ')' || c == ']' || c == '}') && depth > 0) --depth;
      if (c == '.' && depth == 0 &&
          (i_ + 1 == text_.size() || std::isspace(static_cast<unsigned char>(text_[i_ + 1])))) {
        break;  // the clause ended: the call was not closed
      }
      current.text += c;
      step();
    }
    // Back to just after the name: the arguments are scanned as text too.
    i_ = save_i + 1;
    line_ = save_line;
    line_start_ = save_start;
    if (!closed || args.size() > p->args.size() + 1) return;
    for (std::size_t k = 0; k + 1 < args.size() && k < p->args.size(); ++k) {
      const tactical::Argument& a = p->args[k];
      if (a.type != tactical::Value::Type::Number) continue;
      // Leading layout, for the column of the number itself.
      std::string& t = args[k].text;
      std::size_t lead = 0;
      while (lead < t.size() && std::isspace(static_cast<unsigned char>(t[lead]))) {
        if (t[lead] == '\n') {
          ++args[k].line;
          args[k].column = 0;
        }
        ++lead;
        ++args[k].column;
      }
      std::size_t end = t.size();
      while (end > lead && std::isspace(static_cast<unsigned char>(t[end - 1]))) --end;
      const std::string_view written = std::string_view(t).substr(lead, end - lead);
      auto v = literal_number(written);
      if (!v) continue;
      const std::string subject =
          fmt::format("{}/{}: '{}' argument '{}' is {}", name, args.size(), p->name, a.name, written);
      std::string text;
      if (!std::isfinite(*v)) {
        text = subject + ", which is not a finite number";
      } else if (a.min && *v < *a.min) {
        text = fmt::format("{}, below the minimum {}", subject, with_unit(*a.min, a.unit));
      } else if (a.max && *v > *a.max) {
        text = fmt::format("{}, above the maximum {}", subject, with_unit(*a.max, a.unit));
      } else {
        continue;
      }
      problems_.push_back({args[k].line, args[k].column, std::move(text)});
    }
  }

  std::string_view text_;
  const tactical::Catalogue& catalogue_;
  std::optional<tactical::ExecutionLevel> level_;
  std::size_t i_ = 0, line_ = 1, line_start_ = 0;
  std::vector<RulesScanProblem> problems_;
};

}  // namespace

std::vector<RulesScanProblem> scan_primitive_arguments(std::string_view text, const tactical::Catalogue& catalogue) {
  return Scanner(text, catalogue).run();
}

std::vector<RulesScanProblem> scan_unavailable_primitives(std::string_view text, const tactical::Catalogue& catalogue,
                                                          tactical::ExecutionLevel level) {
  if (level == tactical::ExecutionLevel::Phoenix) return {};
  return Scanner(text, catalogue, level).run();
}

}  // namespace strata::strategic
