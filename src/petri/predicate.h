#pragma once
// Questions about a P/T net (docs/verification.md, "Questions"): "can it
// deadlock?", "EF φ" (some reachable marking satisfies φ) and "AG φ" (every
// reachable marking does: not EF !φ), where φ is a predicate over place
// counts:
//
//   question  := "deadlock" | "EF" pred | "AG" pred
//   pred      := or
//   or        := and ("||" and)*
//   and       := unary ("&&" unary)*
//   unary     := "!" unary | "(" pred ")" | "true" | "false" | term op term
//   term      := place | integer          (integer: 0 .. 2^62)
//   op        := "==" | "!=" | "<" | "<=" | ">" | ">="
//   place     := [A-Za-z_][A-Za-z0-9_.-]*  or  "quoted text"  (a place's
//                name, resolved by the caller's PlaceResolver)
//
// The predicate is kept in negation normal form (no "!": negations pushed
// into the comparisons), which is what the stubborn sets (stubborn.h) and
// the structural checks (structural.h) read. Errors carry the 1-based column
// of the question text where they were found.
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"
#include "petri/net.h"

namespace strata::petri {

// A mistake in a text a person typed (a --question, a --replay): its place
// and what is wrong. Columns count bytes from 1.
struct TextError {
  std::size_t line = 0;    // from 1; 0 when the text is one line
  std::size_t column = 0;  // from 1; 0 when the mistake has no column
  std::string message;     // without the place: "no place 'p9'"
  // "column 4: no place 'p9'", or "line 2, column 3: ..." for a text of
  // several lines: the message with its place, for people.
  std::string text() const;
  // InvalidInput, text() as its message.
  core::Error to_core() const;
};

enum class CompareOp { Eq, Ne, Lt, Le, Gt, Ge };

// One side of a comparison: a place's token count or a constant.
struct Term {
  bool is_place = false;
  PlaceId place = 0;
  std::int64_t constant = 0;
  std::int64_t value(std::span<const Tokens> m) const { return is_place ? std::int64_t{m[place]} : constant; }
};

// A node of a predicate in negation normal form.
struct PredicateNode {
  enum class Kind { True, False, Compare, And, Or } kind = Kind::True;
  CompareOp op = CompareOp::Eq;     // Compare
  Term lhs, rhs;                    // Compare
  std::vector<std::uint32_t> kids;  // And, Or: node indexes
};

class Predicate {
 public:
  Predicate();  // true
  // One comparison.
  static Predicate compare(Term lhs, CompareOp op, Term rhs);
  bool holds(std::span<const Tokens> m) const { return holds(root_, m); }
  bool holds(std::uint32_t node, std::span<const Tokens> m) const;
  const PredicateNode& node(std::uint32_t i) const { return nodes_[i]; }
  std::uint32_t root() const { return root_; }
  // The negation, in negation normal form.
  Predicate negated() const;
  // Text that parse_predicate reads back (place names from the net).
  std::string to_string(const Net& net) const;

 private:
  friend class PredicateParser;
  std::uint32_t negate_into(Predicate& out, std::uint32_t node) const;
  std::string text(const Net& net, std::uint32_t node) const;
  std::vector<PredicateNode> nodes_;
  std::uint32_t root_ = 0;
};

// Resolves a place name written in a predicate. Returns the place, or sets
// *why (e.g. "no place 'p9'", "'x' names 2 places: p3, p7").
using PlaceResolver = std::function<std::optional<PlaceId>(std::string_view name, std::string* why)>;

// A resolver for a net's own place names (PNML ids; a mission's names);
// when `labels` is given (by PlaceId), a label names a place too if no
// other place has that label and no place has it as its name.
PlaceResolver net_place_resolver(const Net& net, const std::vector<std::string>* labels = nullptr);

enum class QuestionKind { Deadlock, Reachable, Invariant };  // deadlock, EF φ, AG φ

struct Question {
  QuestionKind kind = QuestionKind::Deadlock;
  Predicate predicate;  // EF φ, AG φ: φ
  // What the search looks for: a deadlock, or a marking satisfying `target`
  // (φ for EF, !φ for AG).
  Predicate target;
};

// Errors: the column of the question text where the mistake is.
core::Result<Question, TextError> parse_question(std::string_view text, const PlaceResolver& places);
// A predicate alone (columns from 1 at its first character).
core::Result<Predicate, TextError> parse_predicate(std::string_view text, const PlaceResolver& places);

}  // namespace strata::petri
