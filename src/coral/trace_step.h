#pragma once
// One step of a counterexample (coral/verifier.h), or of the timing
// analysis's path (coral/timing.h), where the steps cross nets and carry
// their times.
#include <optional>
#include <string>
#include <vector>

namespace strata::coral {

struct TraceStep {
  // Pass: no firing; time passing or the fault starting (its text in `action`).
  enum class Kind { Fire, Answer, Pass } kind = Kind::Fire;
  std::string transition;            // the mission transition fired, or whose action answers
  std::vector<std::string> actions;  // Fire: what it issues ("ASK depth_reached")
  std::string action;                // Answer: the action answering; Pass: what happens
  std::string answer;                // Answer: "1", "0", or the phase's exit
  std::string tactic;                // Answer: "exec", "ask", "ood" or "phase" (the engine's action kinds)
  std::string primitive;             // Answer: the primitive called, or the phase net run
  std::vector<std::string> marks;    // mission places it marks
  // The timing analysis's steps: the instance ("tank/dive_from_surface#1"),
  // its net ("dive_from_surface") and the time since the event (nullopt:
  // before it). A verifier's counterexample leaves them empty.
  std::string instance;
  std::string net;
  std::optional<double> t_s;
};

}  // namespace strata::coral
