#pragma once
// The syntax tree of one CORAL file, as written. Names are not resolved here;
// the checker does that. Every node keeps its source span.
#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "core/source.h"

namespace strata::coral::ast {

struct Name {
  std::string text;
  core::SourceSpan span;
};

struct Literal {
  enum class Kind { Integer, Float, String };
  Kind kind = Kind::Integer;
  std::string text;   // as written (strings: with quotes and escapes)
  std::string value;  // strings: unescaped; numbers: same as text
  core::SourceSpan span;
};

// A primitive as named in a TACTIC: `sleep(1)`, `next_setpt_data`.
struct Call {
  Name name;
  std::vector<Literal> args;
  bool has_parens = false;
  core::SourceSpan span;
};

// w(p, t) or w(t, p): `b*2`.
struct ArcRef {
  Name place;
  std::uint32_t weight = 1;
  core::SourceSpan span;  // the whole `b*2`
};

enum class TacticType { Exec, Ask, Report, Ood, Unknown };

struct Tactic {
  TacticType type = TacticType::Unknown;
  Name type_name;
  std::optional<Call> function;  // EXEC, ASK, OOD
  std::optional<Literal> text;   // REPORT
  std::vector<Name> places;      // outcome places
  core::SourceSpan span;
};

struct Phase {
  Name phase;
  std::vector<Name> places;  // one per exit of the phase, in exit order
  core::SourceSpan span;
};

using Action = std::variant<Tactic, Phase>;

struct Transition {
  Name name;
  int priority = 0;
  std::vector<ArcRef> waits;
  std::vector<Action> actions;
  std::vector<ArcRef> signals;
  core::SourceSpan span;    // the `transition NAME` head
  core::SourceSpan extent;  // from `transition` to its closing '}' (or as far as it was parsed)
};

struct PlaceDecl {
  Name name;
  std::uint32_t initial = 0;
  bool is_exit = false;
  core::SourceSpan initial_span;  // the `= N`, if written
  core::SourceSpan statement;     // the whole `place a, b = 1;` it is declared in
};

struct Net {
  enum class Kind { Phase, Mission };
  Kind kind = Kind::Phase;
  Name name;
  std::vector<PlaceDecl> places;  // `place` and `exit` declarations, in order
  std::vector<Name> exits;        // exit places in declaration order
  std::vector<Literal> data;      // `data "file";` (a mission holds at most one)
  std::vector<Transition> transitions;
  core::SourceSpan span;                  // the `net NAME` / `mission NAME` head
  std::optional<std::uint32_t> body_end;  // offset of the closing '}', when there is one
};

struct Import {
  std::string path;  // as written, unescaped
  core::SourceSpan span;
};

struct File {
  core::FileId id = 0;
  std::vector<Import> imports;
  std::vector<Net> nets;
};

}  // namespace strata::coral::ast
