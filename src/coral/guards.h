#pragma once
// Guards (docs/language.md, "guard"): what a `guard` of a net compiles to.
// A guard is not engine magic: expand_guards writes it into its net as
// places and transitions, so the dump, the PNML export, the studio's
// drawing and `strata verify` all see it. For a guard G with terms
// q_1..q_n polled every P seconds:
//
//   places       G.armed = 1, G.due, G.term2..G.termN, G.tripped, G.cancel
//   G.poll       wait { G.armed }  action { TACTIC(EXEC, sleep(P), G.due) }
//   G.ask1..n    wait { G.due | G.termK }  action { TACTIC(ASK, q_k, ...) }:
//                the answer that trips (1, or 0 for `not q_k`) marks
//                G.tripped, the other G.term(k+1) (G.armed after the last)
//   G.trip       wait { G.tripped }  signal { G.cancel }            (pre-emption)
//   G.drop.p     wait { G.cancel, p } signal { G.cancel }, for every place
//                p of the net but its exits and G's own cycle       (cancellation)
//   G.handle     wait { G.cancel }  action/signal: the guard's handler
//
// Priorities put them above every written transition (at most 1,000,000):
// trip > drop > handle > poll and ask. So once G.tripped is marked nothing
// else fires until the net is empty, and only then the handler runs. The
// CORAL Engine, on firing G.trip, also ends the net's running phases and
// forgets its calls in flight (what a place cannot hold); the verifier's
// analysis net models that with urgent drops of its in-flight places.
#include <cstdint>
#include <string>
#include <vector>

#include "coral/ast.h"

namespace strata::coral {

// The most guards one net may declare: each adds a drop per place of its
// net, so their cost is guards x places (parser: TooManyGuards past it).
inline constexpr std::size_t kMaxGuards = 16;

inline constexpr int kGuardPollPriority = 1'000'001;
inline constexpr int kGuardHandlePriority = 1'000'002;
inline constexpr int kGuardDropPriority = 1'000'003;
inline constexpr int kGuardTripPriority = 1'000'004;

// Appends the places and transitions of every guard of net (each marked
// `generated`). A guard whose name an earlier guard of the net took is
// skipped (the checker reports it). Idempotent only on a fresh net: call once.
void expand_guards(ast::Net& net);

// "system_problem", "not gps_available", "depth_over(30)".
std::string guard_term_text(const ast::GuardTerm& term);

}  // namespace strata::coral
