#pragma once
// The timing analysis's parts (coral/timing.h), shared by its files:
// the model (timing_model.cpp: the program as one time Petri net), the
// graph of timed states (timing_explore.cpp) and the answer read from it
// (timing.cpp). Internal to strata_coral.
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "coral/analysis.h"
#include "coral/timing.h"

namespace strata::coral::timing_detail {

using petri::PlaceId;
using petri::TransitionId;

// ------------------------------------------------------------------ the model

// One net as it runs: the mission, or one PHASE call's phase (parameters bound).
struct Inst {
  const CompiledNet* cn = nullptr;
  AnalysisNet an;
  std::uint32_t place0 = 0;        // the global id of its analysis place 0
  std::uint32_t end_place = 0;     // one past the last global place of it and its calls
  std::uint32_t end_inst = 0;      // one past the last instance of its calls
  std::vector<ast::Literal> args;  // its parameters' values, in order
  std::string path;
  std::vector<int> child;   // by analysis place: the instance its PHASE in flight runs (-1: none)
  std::vector<int> lo, hi;  // by analysis place: a call in flight's answer interval, in ticks (-1: none)
};

// A transition of some instance, and what it means to the question.
struct GlobalTransition {
  std::uint32_t inst = 0;
  TransitionId t = 0;
  bool timed = false;            // an answer to a call in flight
  std::int8_t ask_answer = -1;   // an answer of the fault's ask: 1 or 0; -1 otherwise
  std::uint32_t child_exit = 0;  // a PHASE's end: the child's exit place (global); 0 none
  bool is_to = false;            // issues the TO call
  bool is_event = false;         // a guard trip or phase start that is the event
};

struct Model {
  std::vector<Inst> insts;
  std::vector<GlobalTransition> transitions;
  std::uint32_t places = 0;
  std::vector<std::uint32_t> timed_places;            // global ids of calls in flight with an interval
  std::vector<std::int32_t> lo, hi;                   // by global place
  std::vector<std::int32_t> child;                    // by global place
  std::vector<std::uint32_t> mission_exits;           // global
  std::vector<std::vector<std::uint32_t>> consumers;  // by global place: the transitions it is an input of
  std::optional<std::uint32_t> to_exit;               // To::Exit: the global place
};

// Builds the model of the program's mission for the question; why not, else.
std::optional<std::string> build_model(const Program& program, const BoundQuery& query, const BoundOptions& options,
                                       Model& m);

// ------------------------------------------------------------------ the graph

constexpr std::uint32_t kAdvance = std::numeric_limits<std::uint32_t>::max();
constexpr std::uint32_t kOnset = kAdvance - 1;
constexpr std::uint32_t kTo = std::numeric_limits<std::uint32_t>::max();  // an edge's target: TO happened

struct Edge {
  std::uint32_t to;
  std::uint32_t label;  // a GlobalTransition index, kAdvance or kOnset
  std::uint8_t w;       // ticks counted (after the event)
};

// The timed states and their steps, from the initial state on.
struct TimedGraph {
  std::vector<std::string> keys_;                     // by state: its encoding
  std::vector<std::uint32_t> parent_, parent_label_;  // the BFS tree
  std::vector<std::uint32_t> first_edge_;             // by state, and one past the last
  std::vector<Edge> edges_;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> starts_;  // (pre-event state, label) by start state
  std::vector<std::uint32_t> start_ids_;                         // the states right after the event
  bool immediate_ = false;                                       // the event's own step was TO
  std::pair<std::uint32_t, std::uint32_t> immediate_from_{kAdvance, kAdvance};
  std::string error_;  // why the exploration stopped
};

// Explores the model's timed states into g; false (why in g.error_) when
// they are too many or the model is one the analysis does not take.
bool explore(const Model& m, const BoundQuery& q, const BoundOptions& o, TimedGraph& g);

}  // namespace strata::coral::timing_detail
