#pragma once
// The syntax tree of one CORAL file, as written. Names are not resolved here;
// the checker does that. Every node keeps its source span.
#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "core/call_verb.h"
#include "core/source.h"

namespace strata::coral::ast {

struct Name {
  std::string text;
  core::SourceSpan span;
};

// An argument as written: a literal, or (in a parameterised net) the name of
// one of the net's parameters, whose value the PHASE call that runs the net
// gives (Kind::Parameter).
struct Literal {
  enum class Kind { Integer, Float, String, Parameter };
  Kind kind = Kind::Integer;
  std::string text;   // as written (strings: with quotes and escapes; parameters: the name)
  std::string value;  // strings: unescaped; numbers and parameters: same as text
  core::SourceSpan span;
};

// The value a Kind::Integer or Kind::Float literal reads as; nullopt for a
// string, a parameter, or a number that is not finite as a double (1e999).
std::optional<double> number_value(const Literal& literal);

// A parameter of a phase net: `net leg(x0, y0, string label)`. Parameters are
// data, not structure: each is a number (the default) or a string, given by
// the PHASE call (`PHASE(leg(0, 0, "a"), ...)`) and used as an argument of a
// primitive or of a nested PHASE call.
enum class ParamType { Number, String };

struct Param {
  Name name;
  ParamType type = ParamType::Number;
  core::SourceSpan span;  // `string label` or `x0`
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

// A TACTIC's type is the call verb of its primitive (EXEC, ASK, OOD, REPORT).
using TacticType = core::CallVerb;

struct Tactic {
  std::optional<TacticType> type;  // nullopt: not one of the four (diagnosed by the parser)
  Name type_name;
  std::optional<Call> function;  // EXEC, ASK, OOD
  std::optional<Literal> text;   // REPORT
  std::vector<Name> places;      // outcome places
  core::SourceSpan span;
};

struct Phase {
  Name phase;
  std::vector<Literal> args;  // `PHASE(leg(0, 0, 100, 0), ...)`: the phase's parameters, in order
  bool has_parens = false;    // `PHASE(leg(), ...)`
  std::vector<Name> places;   // one per exit of the phase, in exit order
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
  bool generated = false;   // made by expand_guards (coral/guards.h), not written
};
// One term of a guard's condition: `system_problem` trips the guard when the
// ASK answers 1, `not gps_available` when it answers 0.
struct GuardTerm {
  bool negated = false;
  Call ask;
  core::SourceSpan span;  // the whole term, `not` included
};
// `guard NAME every PERIOD { when { TERM, ... } action { ... } signal { ... } }`
// (docs/language.md, "guard"): polled every PERIOD simulated seconds while
// its net runs; when a term trips, everything running in the net is
// pre-empted and the handler (its action and signal) takes over.
struct Guard {
  Name name;
  Literal period;  // a number, or a number parameter of the net
  std::vector<GuardTerm> when;
  std::vector<Action> actions;
  std::vector<ArcRef> signals;
  core::SourceSpan span;    // the `guard NAME` head
  core::SourceSpan extent;  // from `guard` to its closing '}'
};

struct PlaceDecl {
  Name name;
  std::uint32_t initial = 0;
  bool is_exit = false;
  bool generated = false;         // made by expand_guards (coral/guards.h), not written
  core::SourceSpan initial_span;  // the `= N`, if written
  core::SourceSpan statement;     // the whole `place a, b = 1;` it is declared in
};

struct Net {
  enum class Kind { Phase, Mission };
  Kind kind = Kind::Phase;
  Name name;
  std::vector<Param> params;      // phase nets only: `net leg(x0, y0) { ... }`
  std::vector<PlaceDecl> places;  // `place` and `exit` declarations, in order
  std::vector<Name> exits;        // exit places in declaration order
  std::vector<Literal> data;      // `data "file";` (a mission holds at most one)
  std::vector<Transition> transitions;
  std::vector<Guard> guards;  // as written; expand_guards adds their places and transitions
  // `require "FROM -> TO within S";` (a mission): a reaction time that
  // `strata verify` proves (docs/verification.md, "Reaction time"). The
  // literal is the string as written.
  std::vector<Literal> requirements;
  core::SourceSpan span;                  // the `net NAME` / `mission NAME` head
  std::optional<std::uint32_t> body_end;  // offset of the closing '}', when there is one
};

struct Import {
  std::string path;  // as written, unescaped; for `import NAME;`, the NAME
  core::SourceSpan span;
  bool by_name = false;  // `import NAME;`: a module of the phase library, not a path
};

struct File {
  core::FileId id = 0;
  std::vector<Import> imports;
  std::vector<Net> nets;
};

}  // namespace strata::coral::ast
