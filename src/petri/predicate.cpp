#include "petri/predicate.h"

#include <algorithm>
#include <cctype>
#include <map>

#include <fmt/format.h>

namespace strata::petri {

namespace {

constexpr std::int64_t kMaxPredicateConstant = std::int64_t{1} << 62;

bool compare_values(CompareOp op, std::int64_t a, std::int64_t b) {
  switch (op) {
    case CompareOp::Eq: return a == b;
    case CompareOp::Ne: return a != b;
    case CompareOp::Lt: return a < b;
    case CompareOp::Le: return a <= b;
    case CompareOp::Gt: return a > b;
    case CompareOp::Ge: return a >= b;
  }
  return false;
}

CompareOp negate_op(CompareOp op) {
  switch (op) {
    case CompareOp::Eq: return CompareOp::Ne;
    case CompareOp::Ne: return CompareOp::Eq;
    case CompareOp::Lt: return CompareOp::Ge;
    case CompareOp::Le: return CompareOp::Gt;
    case CompareOp::Gt: return CompareOp::Le;
    case CompareOp::Ge: return CompareOp::Lt;
  }
  return op;
}

const char* op_text(CompareOp op) {
  switch (op) {
    case CompareOp::Eq: return "==";
    case CompareOp::Ne: return "!=";
    case CompareOp::Lt: return "<";
    case CompareOp::Le: return "<=";
    case CompareOp::Gt: return ">";
    case CompareOp::Ge: return ">=";
  }
  return "?";
}

bool is_name_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool is_name_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '-'; }

// A name as parse_predicate reads it back: bare when it is a bare name and
// no keyword, else quoted.
std::string predicate_place_text(std::string_view name) {
  bool bare = !name.empty() && is_name_start(name[0]) && name != "true" && name != "false";
  for (char c : name) bare = bare && is_name_char(c);
  if (bare) return std::string(name);
  std::string out = "\"";
  for (char c : name) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

}  // namespace

Predicate::Predicate() : nodes_{PredicateNode{}}, root_{0} {}

Predicate Predicate::compare(Term lhs, CompareOp op, Term rhs) {
  Predicate p;
  p.nodes_[0].kind = PredicateNode::Kind::Compare;
  p.nodes_[0].lhs = lhs;
  p.nodes_[0].op = op;
  p.nodes_[0].rhs = rhs;
  return p;
}

bool Predicate::holds(std::uint32_t i, std::span<const Tokens> m) const {
  const PredicateNode& n = nodes_[i];
  switch (n.kind) {
    case PredicateNode::Kind::True: return true;
    case PredicateNode::Kind::False: return false;
    case PredicateNode::Kind::Compare: return compare_values(n.op, n.lhs.value(m), n.rhs.value(m));
    case PredicateNode::Kind::And:
      return std::all_of(n.kids.begin(), n.kids.end(), [&](std::uint32_t k) { return holds(k, m); });
    case PredicateNode::Kind::Or:
      return std::any_of(n.kids.begin(), n.kids.end(), [&](std::uint32_t k) { return holds(k, m); });
  }
  return false;
}

std::uint32_t Predicate::negate_into(Predicate& out, std::uint32_t i) const {
  PredicateNode n = nodes_[i];
  switch (n.kind) {
    case PredicateNode::Kind::True: n.kind = PredicateNode::Kind::False; break;
    case PredicateNode::Kind::False: n.kind = PredicateNode::Kind::True; break;
    case PredicateNode::Kind::Compare: n.op = negate_op(n.op); break;
    case PredicateNode::Kind::And:
    case PredicateNode::Kind::Or:
      n.kind = n.kind == PredicateNode::Kind::And ? PredicateNode::Kind::Or : PredicateNode::Kind::And;
      for (std::uint32_t& k : n.kids) k = negate_into(out, k);
      break;
  }
  out.nodes_.push_back(std::move(n));
  return static_cast<std::uint32_t>(out.nodes_.size() - 1);
}

Predicate Predicate::negated() const {
  Predicate out;
  out.nodes_.clear();
  out.root_ = negate_into(out, root_);
  return out;
}

std::string Predicate::text(const Net& net, std::uint32_t i) const {
  const PredicateNode& n = nodes_[i];
  auto term = [&](const Term& t) {
    return t.is_place ? predicate_place_text(net.place_name(t.place)) : std::to_string(t.constant);
  };
  switch (n.kind) {
    case PredicateNode::Kind::True: return "true";
    case PredicateNode::Kind::False: return "false";
    case PredicateNode::Kind::Compare: return fmt::format("{} {} {}", term(n.lhs), op_text(n.op), term(n.rhs));
    case PredicateNode::Kind::And:
    case PredicateNode::Kind::Or: {
      std::string out = "(";
      for (std::size_t k = 0; k < n.kids.size(); ++k) {
        if (k) out += n.kind == PredicateNode::Kind::And ? " && " : " || ";
        out += text(net, n.kids[k]);
      }
      return out + ")";
    }
  }
  return "";
}

std::string Predicate::to_string(const Net& net) const { return text(net, root_); }

std::string TextError::text() const {
  if (column == 0) return message;
  if (line > 0) return fmt::format("line {}, column {}: {}", line, column, message);
  return fmt::format("column {}: {}", column, message);
}

core::Error TextError::to_core() const { return core::Error{core::ErrorCode::InvalidInput, text()}; }

// Recursive descent over the question text; `!` is applied while parsing
// (each node is built already negated when under an odd number of `!`).
class PredicateParser {
 public:
  PredicateParser(std::string_view text, std::size_t column0, const PlaceResolver& places)
      : s_(text), column0_(column0), places_(places) {}

  core::Result<Predicate, TextError> parse_all() {
    out_.nodes_.clear();
    skip_space();
    if (at_end()) return fail(pos_, "expected a predicate");
    auto root = parse_or(false, 0);
    if (failed()) return error_;
    skip_space();
    if (!at_end()) {
      if (peek() == ')') return fail(pos_, "unmatched ')'");
      return fail(pos_, fmt::format("unexpected '{}' after the predicate", token_text()));
    }
    out_.root_ = root;
    return std::move(out_);
  }

 private:
  static constexpr int kMaxDepth = 200;

  bool at_end() const { return pos_ >= s_.size(); }
  char peek(std::size_t k = 0) const { return pos_ + k < s_.size() ? s_[pos_ + k] : '\0'; }
  void skip_space() {
    while (!at_end() && std::isspace(static_cast<unsigned char>(peek()))) ++pos_;
  }
  bool eat(std::string_view tok) {
    skip_space();
    if (s_.substr(pos_, tok.size()) != tok) return false;
    pos_ += tok.size();
    return true;
  }
  std::string token_text() const {
    if (at_end()) return "end of text";
    std::size_t end = pos_ + 1;
    if (is_name_char(s_[pos_])) {
      while (end < s_.size() && is_name_char(s_[end])) ++end;
    } else if (std::string_view("&|=!<>").find(s_[pos_]) != std::string_view::npos) {
      while (end < s_.size() && end < pos_ + 2 && std::string_view("&|=!<>").find(s_[end]) != std::string_view::npos)
        ++end;
    }
    return std::string(s_.substr(pos_, end - pos_));
  }
  bool failed() const { return !error_.message.empty(); }
  TextError fail(std::size_t at, std::string message) {
    if (!failed()) error_ = TextError{0, column0_ + at, std::move(message)};
    return error_;
  }
  std::uint32_t add(PredicateNode n) {
    out_.nodes_.push_back(std::move(n));
    return static_cast<std::uint32_t>(out_.nodes_.size() - 1);
  }
  // A junction of kids; under negation "&&" becomes "||" (De Morgan).
  std::uint32_t junction(bool is_and, bool negated, std::vector<std::uint32_t> kids) {
    if (kids.size() == 1) return kids[0];
    PredicateNode n;
    n.kind = is_and != negated ? PredicateNode::Kind::And : PredicateNode::Kind::Or;
    n.kids = std::move(kids);
    return add(std::move(n));
  }

  std::uint32_t parse_or(bool negated, int depth) {
    std::vector<std::uint32_t> kids{parse_and(negated, depth)};
    while (!failed() && eat("||")) kids.push_back(parse_and(negated, depth));
    return junction(false, negated, std::move(kids));
  }
  std::uint32_t parse_and(bool negated, int depth) {
    std::vector<std::uint32_t> kids{parse_unary(negated, depth)};
    while (!failed() && eat("&&")) kids.push_back(parse_unary(negated, depth));
    return junction(true, negated, std::move(kids));
  }
  std::uint32_t parse_unary(bool negated, int depth) {
    if (failed()) return 0;
    if (depth > kMaxDepth) {
      fail(pos_, fmt::format("nested more than {} deep", kMaxDepth));
      return 0;
    }
    skip_space();
    if (at_end()) {
      fail(pos_, "expected a comparison, '(', '!', true or false, found the end of the text");
      return 0;
    }
    if (peek() == '!' && peek(1) != '=') {
      ++pos_;
      return parse_unary(!negated, depth + 1);
    }
    if (peek() == '(') {
      const std::size_t open = pos_++;
      const std::uint32_t inner = parse_or(negated, depth + 1);
      if (failed()) return 0;
      if (!eat(")")) {
        skip_space();
        fail(pos_,
             fmt::format("expected ')' to close the '(' at column {}, found '{}'", column0_ + open, token_text()));
        return 0;
      }
      return inner;
    }
    const std::size_t start = pos_;
    if (peek() != '"' && is_name_start(peek())) {
      const std::string word = token_text();
      std::size_t after = pos_ + word.size();
      while (after < s_.size() && std::isspace(static_cast<unsigned char>(s_[after]))) ++after;
      const bool operator_follows =
          after < s_.size() && std::string_view("=!<>").find(s_[after]) != std::string_view::npos;
      if ((word == "true" || word == "false") && !operator_follows) {
        pos_ += word.size();
        PredicateNode n;
        n.kind = (word == "true") != negated ? PredicateNode::Kind::True : PredicateNode::Kind::False;
        return add(std::move(n));
      }
    }
    PredicateNode n;
    n.kind = PredicateNode::Kind::Compare;
    if (!parse_term(n.lhs)) return 0;
    const std::size_t term_end = pos_;
    skip_space();
    const std::size_t op_at = pos_;
    static constexpr std::pair<std::string_view, CompareOp> kOps[] = {{"==", CompareOp::Eq}, {"!=", CompareOp::Ne},
                                                                      {"<=", CompareOp::Le}, {">=", CompareOp::Ge},
                                                                      {"<", CompareOp::Lt},  {">", CompareOp::Gt}};
    bool found = false;
    for (const auto& [tok, op] : kOps) {
      if (s_.substr(pos_, tok.size()) == tok) {
        pos_ += tok.size();
        n.op = op;
        found = true;
        break;
      }
    }
    if (!found) {
      if (peek() == '=') {
        fail(op_at, "'=' is not a comparison: write '=='");
      } else {
        fail(op_at, fmt::format("expected a comparison (== != < <= > >=) after '{}', found '{}'",
                                s_.substr(start, term_end - start), token_text()));
      }
      return 0;
    }
    if (!parse_term(n.rhs)) return 0;
    if (negated) n.op = negate_op(n.op);
    return add(std::move(n));
  }

  bool parse_term(Term& t) {
    skip_space();
    const std::size_t start = pos_;
    if (std::isdigit(static_cast<unsigned char>(peek()))) {
      std::int64_t v = 0;
      while (std::isdigit(static_cast<unsigned char>(peek()))) {
        const int digit = peek() - '0';
        if (v > (kMaxPredicateConstant - digit) / 10) {
          fail(start, "number too large (at most 2^62)");
          return false;
        }
        v = v * 10 + digit;
        ++pos_;
      }
      if (is_name_char(peek())) {
        fail(start, fmt::format("'{}' is neither a number nor a place name", s_.substr(start, pos_ + 1 - start)));
        return false;
      }
      t.is_place = false;
      t.constant = v;
      return true;
    }
    std::string name;
    if (peek() == '"') {
      ++pos_;
      for (;;) {
        if (at_end()) {
          fail(start, "unterminated quoted place name");
          return false;
        }
        char c = s_[pos_++];
        if (c == '"') break;
        if (c == '\\' && !at_end()) c = s_[pos_++];
        name += c;
      }
    } else if (is_name_start(peek())) {
      while (is_name_char(peek())) name += s_[pos_++];
    } else if (peek() == '-') {
      fail(start, "negative numbers are not allowed: a place holds 0 or more tokens");
      return false;
    } else {
      fail(start, fmt::format("expected a place name or a number, found '{}'", token_text()));
      return false;
    }
    std::string why;
    std::optional<PlaceId> p = places_(name, &why);
    if (!p) {
      fail(start, why.empty() ? fmt::format("no place '{}'", name) : why);
      return false;
    }
    t.is_place = true;
    t.place = *p;
    return true;
  }

  std::string_view s_;
  std::size_t column0_;
  const PlaceResolver& places_;
  std::size_t pos_ = 0;
  TextError error_;  // the first mistake; its message is empty while there is none
  Predicate out_;
};

core::Result<Predicate, TextError> parse_predicate(std::string_view text, const PlaceResolver& places) {
  return PredicateParser(text, 1, places).parse_all();
}

core::Result<Question, TextError> parse_question(std::string_view text, const PlaceResolver& places) {
  std::size_t i = 0;
  while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
  std::size_t end = i;
  while (end < text.size() && is_name_char(text[end])) ++end;
  const std::string_view word = text.substr(i, end - i);
  Question q;
  if (word == "deadlock") {
    std::size_t rest = end;
    while (rest < text.size() && std::isspace(static_cast<unsigned char>(text[rest]))) ++rest;
    if (rest < text.size()) {
      return TextError{0, rest + 1, "nothing may follow 'deadlock'"};
    }
    q.kind = QuestionKind::Deadlock;
    return q;
  }
  if (word != "EF" && word != "AG") {
    return TextError{0, i + 1,
                     fmt::format("a question is 'deadlock', 'EF <predicate>' or 'AG <predicate>'{}",
                                 word.empty() ? "" : fmt::format(", not '{}'", word))};
  }
  auto pred = PredicateParser(text.substr(end), end + 1, places).parse_all();
  if (!pred) return pred.error();
  q.kind = word == "EF" ? QuestionKind::Reachable : QuestionKind::Invariant;
  q.predicate = std::move(pred).value();
  q.target = q.kind == QuestionKind::Reachable ? q.predicate : q.predicate.negated();
  return q;
}

PlaceResolver net_place_resolver(const Net& net, const std::vector<std::string>* labels) {
  // Label -> places with it, built once (a copy lives in the resolver).
  std::map<std::string, std::vector<PlaceId>, std::less<>> by_label;
  if (labels) {
    for (PlaceId p = 0; p < labels->size() && p < net.place_count(); ++p) by_label[(*labels)[p]].push_back(p);
  }
  return [&net, by_label = std::move(by_label)](std::string_view name, std::string* why) -> std::optional<PlaceId> {
    if (auto p = net.find_place(name)) return p;
    auto it = by_label.find(name);
    if (it == by_label.end()) {
      *why = fmt::format("no place '{}'", name);
      return std::nullopt;
    }
    if (it->second.size() > 1) {
      std::string ids;
      for (std::size_t k = 0; k < it->second.size() && k < 5; ++k) {
        ids += fmt::format("{}{}", k ? ", " : "", net.place_name(it->second[k]));
      }
      *why = fmt::format("'{}' names {} places ({}{}): use an id", name, it->second.size(), ids,
                         it->second.size() > 5 ? ", ..." : "");
      return std::nullopt;
    }
    return it->second[0];
  };
}

}  // namespace strata::petri
