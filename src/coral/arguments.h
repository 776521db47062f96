#pragma once
// Internal to strata_coral: the checks of arguments and phase parameters
// (docs/language.md, "phase parameters"), used by the checker.
//
// Each parameter of a phase net gets the range its uses allow: the
// intersection of the catalogue's min..max of every primitive argument it is
// passed to, in its net or, through nested PHASE calls, in the phases it is
// passed on to. A PHASE call is then checked where it is written: its
// literal arguments against those ranges, so `PHASE(leg(0, 0, 5000, 0), ...)`
// is reported at the 5000, with a note at the use that limits it. The ranges
// are computed once per net (callees first), so the work is linear in the
// size of the load however deep the phases nest, and a PHASE cycle (reported
// by the checker as PhaseRecursion) cannot make it loop.
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "coral/ast.h"
#include "coral/checker.h"
#include "core/diagnostic.h"

namespace strata::coral {

// The nets of a load by name (the first declaration of each).
using NetLibrary = std::unordered_map<std::string, const ast::Net*>;

class ArgumentChecker {
 public:
  // Computes the parameters' ranges; options.primitive may be unset (then
  // only names, counts and parameter types are checked).
  ArgumentChecker(const NetLibrary& library, core::DiagnosticSink& sink, const CheckOptions& options);

  // Duplicate parameter names in net.
  void check_params(const ast::Net& net);
  // Every Kind::Parameter argument must name a parameter of net.
  void check_names(const ast::Net& net, const std::vector<ast::Literal>& args);
  // A primitive call's arguments against its signature: each literal's type
  // and range, each parameter's type. The count is the checker's.
  void check_primitive_args(const ast::Net& net, const ast::Call& call, const PrimitiveSignature& sig);
  // `TACTIC(REPORT, name)`: name must be a string parameter of net
  // (ArgumentType if a number; TacticArguments if it is no parameter, which
  // the parser already refuses for text it parsed).
  void check_report_param(const ast::Net& net, const ast::Literal& name);
  // A PHASE call's arguments against the callee's parameters: count, types,
  // and each literal number against the parameter's range.
  void check_phase_args(const ast::Net& caller, const ast::Phase& call, const ast::Net& callee);

 private:
  struct Bound {
    double value = 0;
    std::string unit;
    std::string what;  // "'heading' argument 'degrees'"
    core::SourceSpan use;
  };
  struct Range {
    std::optional<Bound> lo, hi;
  };

  void compute_ranges();
  void narrow(const ast::Net& net, std::vector<Range>& ranges, const std::vector<ast::Literal>& args,
              const std::vector<Range>& wanted);
  std::optional<std::size_t> param_index(const ast::Net& net, std::string_view name) const;
  const ast::Net* callee_of(const ast::Phase& call) const;

  const NetLibrary& library_;
  core::DiagnosticSink& sink_;
  const CheckOptions& options_;
  std::unordered_map<const ast::Net*, std::vector<Range>> ranges_;
};

}  // namespace strata::coral
