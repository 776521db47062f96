#pragma once
// Answers one question about a P/T net (predicate.h: deadlock, EF φ, AG φ)
// and stops at the first witness, where the full exploration (explorer.h)
// walks every reachable marking.
//
// First the structural checks (structural.h); then a depth-first search
// from the initial marking that fires, at each marking, the enabled
// transitions of a stubborn set (stubborn.h), or all of them with
// `reduction = false`. The reduction never changes the answer; it changes
// which witness is found and how many markings are visited. The witness is
// the firing sequence from the initial marking to the marking found (the
// path of the search: not the shortest); replay() checks it.
//
// The stubborn sets are computed while they pay for themselves (see
// question.cpp). The search decides every question itself: it never hands
// one over to the full exploration.
//
// Limits: max_states, max_memory_bytes, deadline and the progress callback stop the
// search; the answer is then NotDecided, never a yes or no it has not seen.
//
// Storage: every visited marking in the full exploration's packed storage
// (packed_markings.h: bit fields, widened as counts grow, in the slots of an
// open-addressing hash table), and the search stack.
// Threads: one.
#include <chrono>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "core/result.h"
#include "petri/explorer.h"  // ExploreProgress
#include "petri/net.h"
#include "petri/predicate.h"

namespace strata::petri {

struct QuestionOptions {
  bool reduction = true;             // stubborn sets
  bool structural = true;            // try structural.h first
  std::uint64_t max_states = 0;      // 0: no limit
  std::size_t max_memory_bytes = 0;  // markings and their index; 0: no limit
  // Past it the search stops (checked every 4,096 new markings).
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
  // Called about every progress_every new markings; false stops the search.
  std::function<bool(const ExploreProgress&)> progress;
  std::uint64_t progress_every = 1u << 20;
  // Markings with a token in one of these have no successors (a mission
  // phase ends at its exits: docs/verification.md) and are no deadlocks.
  // With terminal places the search uses no stubborn sets: a transition
  // marking one would disable every other, which their rules do not see.
  std::vector<PlaceId> terminal_places;
};

enum class Answer { Yes, No, NotDecided };

struct QuestionResult {
  // deadlock: Yes when a reachable marking enables nothing; EF φ: Yes when
  // a reachable marking satisfies φ; AG φ: Yes when every one does.
  Answer answer = Answer::NotDecided;
  // When the search found a marking (a deadlock, φ for EF, !φ for AG): the
  // transitions fired from the initial marking, and that marking.
  bool has_witness = false;
  std::vector<TransitionId> witness;
  Marking witness_marking;
  std::string structural_reason;  // set when structure alone answered
  std::string stopped_why;        // when NotDecided
  std::uint64_t states = 0;       // markings visited (stored)
  std::uint64_t edges = 0;        // transitions fired by the search
  std::size_t memory_bytes = 0;   // the store at the end
};

QuestionResult answer_question(const Net& net, const Question& question, const QuestionOptions& options = {});

// Fires `sequence` from the initial marking.
struct ReplayResult {
  std::size_t fired = 0;  // transitions fired
  bool complete = false;  // every one was enabled in turn
  Marking marking;        // the marking reached (before the one not enabled)
  bool deadlock = false;  // that marking enables nothing
  std::string error;      // when not complete: which transition, and why
};

ReplayResult replay(const Net& net, std::span<const TransitionId> sequence);

// Transition names separated by spaces, commas or newlines ('#' starts a
// comment to the end of its line). Errors: the name's column, and its line
// when the text has several lines.
core::Result<std::vector<TransitionId>, TextError> parse_sequence(std::string_view text, const Net& net);

}  // namespace strata::petri
