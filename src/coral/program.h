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

// A guard of a net (coral/guards.h) and the nodes it compiled to.
struct CompiledGuard {
  std::string name;
  std::string period;              // as written: "1", "2.5", or a parameter's name
  std::vector<std::string> terms;  // "system_problem", "not gps_available"
  petri::TransitionId poll = 0, trip = 0, handle = 0;
  std::vector<petri::TransitionId> asks;  // one per term, in order
  std::vector<petri::PlaceId> loop;       // armed, due, term2.., tripped: the poll cycle's places
  petri::PlaceId cancel = 0;
  core::SourceSpan span;  // the `guard NAME` head
};

// What a transition of a compiled net is to its guards: a written
// transition (None), or a node a guard compiled to.
enum class GuardRole : std::uint8_t { None, Poll, Ask, Trip, Drop, Handle };
struct GuardNode {
  GuardRole role = GuardRole::None;
  std::uint32_t guard = 0;  // index in CompiledNet::guards
  std::uint32_t term = 0;   // Ask: the term's index
};

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
  std::vector<CompiledGuard> guards;               // in declaration order
  std::vector<GuardNode> guard_nodes;              // by TransitionId; empty when the net has no guard
  std::vector<bool> place_generated;               // by PlaceId; empty when the net has no guard
  // `require "...";` (a mission): the question and where it is written.
  struct Requirement {
    std::string text;
    core::SourceSpan span;
  };
  std::vector<Requirement> requirements;

  // The transition's part in a guard (role None for a written transition).
  GuardNode guard_node(petri::TransitionId t) const { return t < guard_nodes.size() ? guard_nodes[t] : GuardNode{}; }
  bool generated(petri::TransitionId t) const { return guard_node(t).role != GuardRole::None; }
  bool generated_place(petri::PlaceId p) const { return p < place_generated.size() && place_generated[p]; }
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
