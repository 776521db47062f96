#pragma once
// The analysis net of one compiled CORAL net (docs/verification.md): the
// net as the CORAL Engine runs it, with the vehicle's answers made explicit.
// Every place and transition of the mission stays; each TACTIC or PHASE
// action that waits for an answer gets an in-flight place, marked when its
// transition fires, and one outcome transition per possible answer:
//
//   EXEC f, OOD f       one: f answered 1, marks the done place
//   ASK q               two: q answered 1 (true place), answered 0 (false place)
//   PHASE n(p_1..p_k)   one per exit of n: the phase ended at that exit, marks p_i
//   REPORT              none: immediate, nothing to wait for
//
// (EXEC or OOD answered 0, a lost link or a time-out fail the whole
// mission; they are not paths of the net.) Names in the analysis net are
// the mission's for its own nodes; an in-flight place is
// "TRANSITION.PRIMITIVE" (".2", ".3" after it for a second action on the
// same primitive), and an outcome transition is the in-flight place's name
// with ".yes", ".no" (ASK), ".done" (EXEC, OOD) or ".EXIT" (PHASE) after
// it. CORAL names have no '.', so these never collide with the mission's.
//
// Guards (coral/guards.h): their places and transitions are in the compiled
// net already. The analysis adds what the engine does beside them: when a
// guard G trips it forgets every call in flight of the net, so each in-flight
// place f not of G's own cycle gets a drop "G.drop.f" (wait G.cancel and f,
// signal G.cancel), and G's trip, drops and handler are **urgent**: in a
// marking where one is enabled, only those of the highest priority may
// happen (no other firing, no answer), as in the engine, which runs them
// all within the reply that tripped the guard.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "coral/program.h"
#include "petri/net.h"

namespace strata::coral {

struct AnalysisNet {
  // What an analysis-net transition stands for.
  struct Step {
    // Transition: a mission transition (action = its actions, issued on
    // firing). Outcome: an answer to action `action` of `transition`.
    // Forget: guard `answer` drops action `action` of `transition` in flight.
    enum class Kind { Transition, Outcome, Forget } kind = Kind::Transition;
    petri::TransitionId transition = 0;  // in the compiled net
    std::size_t action = 0;              // Outcome: index in the transition's actions
    std::size_t answer = 0;              // Outcome: ASK 0 = true, 1 = false; PHASE the exit index
  };
  // What an analysis-net place stands for.
  struct PlaceOrigin {
    std::optional<petri::PlaceId> place;  // a mission place (same id in both nets)
    petri::TransitionId transition = 0;   // in flight: the action's transition
    std::size_t action = 0;               // in flight: its index
  };

  const CompiledNet* source = nullptr;
  petri::Net net;
  std::vector<Step> steps;            // by analysis TransitionId
  std::vector<PlaceOrigin> places;    // by analysis PlaceId
  std::vector<petri::PlaceId> exits;  // the mission net's exits (same ids)
  std::vector<bool> urgent;           // by analysis TransitionId: a guard's trip, drop or handler

  // A step of a guard's poll cycle: its poll or ask firing, or an answer to them.
  bool guard_cycle(petri::TransitionId t) const;
  // An answer of a guard's ask that trips it (a fault found).
  bool trips(petri::TransitionId t) const;
};

// Which exits of a phase its own analysis found reachable, by phase name;
// a phase not listed may end at any of its exits.
struct PhaseExits {
  std::string phase;
  std::vector<bool> reachable;  // by exit index
};

// The places of the compiled net keep their ids (0..n-1); in-flight places
// follow, transitions likewise. `phase_exits` narrows a PHASE action's
// outcomes to the exits its phase can reach.
AnalysisNet build_analysis_net(const Program& program, const CompiledNet& net,
                               const std::vector<PhaseExits>& phase_exits = {});

// "ASK depth_reached", "EXEC sleep(1)", "PHASE initialize", "REPORT "text"".
std::string action_text(const ActionSpec& action);
// The answer of an outcome: "1", "0" or the phase's exit name.
std::string answer_text(const Program& program, const ActionSpec& action, std::size_t answer);

}  // namespace strata::coral
