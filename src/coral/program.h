#pragma once
// The compiled form of a CORAL load: one petri::Net per net plus the action
// table (what each transition issues when it fires, and which places the
// replies mark). This is what the CORAL Engine runs and `strata dump` prints.
#include <optional>
#include <string>
#include <vector>

#include "coral/ast.h"
#include "petri/net.h"

namespace strata::coral {

struct ActionSpec {
  enum class Kind { Tactic, Phase };
  Kind kind = Kind::Tactic;
  ast::TacticType tactic = ast::TacticType::Exec;  // Kind::Tactic only
  std::string target;                              // EXEC/ASK/OOD: the primitive; PHASE: the phase net; REPORT: empty
  // The arguments of the primitive, or of the PHASE call (the phase's
  // parameters, in order). In a parameterised net an argument may be
  // Kind::Parameter: the engine substitutes the value the phase was run with.
  std::vector<ast::Literal> args;
  std::string text;  // REPORT only: its string, or empty when args holds the parameter it reports
  // Places marked by the outcome: EXEC/OOD [done]; ASK [true, false];
  // REPORT []; PHASE one per exit of the phase, in exit order.
  std::vector<petri::PlaceId> outcomes;
  core::SourceSpan span;
};

// How deep PHASE calls may nest when a mission runs: the mission net is at
// depth 0, a phase it calls at 1. The CORAL Engine stops a run that would go
// deeper (a phase that runs itself would recurse for ever); `strata verify`
// checks the same limit (phase_depth) before a run starts.
inline constexpr std::size_t kMaxPhaseDepth = 64;

struct CompiledNet {
  std::string name;
  ast::Net::Kind kind = ast::Net::Kind::Phase;
  std::vector<ast::Param> params;  // phase nets: the parameters, in order
  petri::Net net;
  std::vector<std::vector<ActionSpec>> actions;  // indexed by TransitionId
  std::vector<petri::PlaceId> exits;             // in declaration order
  std::string data_file;                         // mission only: resolved against the mission's folder, or empty
  std::string data_as_written;                   // the path as the mission wrote it
  std::string source_file;                       // the file that declares the net
  core::SourceSpan span;
  std::vector<core::SourceSpan> place_spans;       // by PlaceId: the name where declared
  std::vector<core::SourceSpan> transition_spans;  // by TransitionId: the `transition NAME` head
};

struct Program {
  std::vector<CompiledNet> nets;  // in load order
  std::optional<std::size_t> mission;

  const CompiledNet* find(std::string_view name) const;
};

// CORAL's spelling of a TACTIC type: "EXEC", "ASK", "REPORT", "OOD".
std::string_view tactic_type_name(ast::TacticType type);
// The type CORAL spells so; nullopt for anything else.
std::optional<ast::TacticType> parse_tactic_type(std::string_view text);

// "leg(0, 0, 100, 0)" for a PHASE action with arguments, "leg" without:
// how dumps, exports and the studio show the call.
std::string phase_call_text(const ActionSpec& action);
// "leg(x0, y0, string label)", or the bare name of a net without parameters.
std::string net_head_text(const CompiledNet& net);

// Stable text of a compiled net or of a whole program, for golden tests and
// `strata dump`.
std::string dump_net(const CompiledNet& net);
std::string dump_program(const Program& program);

}  // namespace strata::coral
