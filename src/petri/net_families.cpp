#include "petri/net_families.h"

#include <string>

namespace strata::petri {

Net dining_philosophers(unsigned n) {
  NetBuilder b;
  b.reserve(std::size_t{5} * n, std::size_t{5} * n, std::size_t{16} * n);
  std::vector<PlaceId> think(n), fork(n), left(n), right(n), eat(n);
  for (unsigned i = 0; i < n; ++i) {
    const std::string k = std::to_string(i + 1);
    think[i] = b.add_place("Think_" + k, 1);
    fork[i] = b.add_place("Fork_" + k, 1);
    left[i] = b.add_place("Catch1_" + k);   // holds its left fork
    right[i] = b.add_place("Catch2_" + k);  // holds its right fork
    eat[i] = b.add_place("Eat_" + k);
  }
  for (unsigned i = 0; i < n; ++i) {
    const std::string k = std::to_string(i + 1);
    const unsigned j = (i + 1) % n;  // the right fork is the next philosopher's left one
    TransitionId take_left = b.add_transition("FF1a_" + k);
    b.add_input(take_left, think[i]);
    b.add_input(take_left, fork[i]);
    b.add_output(take_left, left[i]);
    TransitionId take_right = b.add_transition("FF1b_" + k);
    b.add_input(take_right, think[i]);
    b.add_input(take_right, fork[j]);
    b.add_output(take_right, right[i]);
    TransitionId then_right = b.add_transition("FF2a_" + k);
    b.add_input(then_right, left[i]);
    b.add_input(then_right, fork[j]);
    b.add_output(then_right, eat[i]);
    TransitionId then_left = b.add_transition("FF2b_" + k);
    b.add_input(then_left, right[i]);
    b.add_input(then_left, fork[i]);
    b.add_output(then_left, eat[i]);
    TransitionId release = b.add_transition("End_" + k);
    b.add_input(release, eat[i]);
    b.add_output(release, think[i]);
    b.add_output(release, fork[i]);
    b.add_output(release, fork[j]);
  }
  return std::move(b).build();
}

Net referendum(unsigned n) {
  NetBuilder b;
  b.reserve(3 * n + 1, 2 * n + 1, 5 * n + 1);
  PlaceId ready = b.add_place("ready", 1);
  TransitionId start = b.add_transition("start");
  b.add_input(start, ready);
  for (unsigned i = 0; i < n; ++i) {
    const std::string k = std::to_string(i + 1);
    PlaceId voting = b.add_place("voting_" + k);
    PlaceId yes = b.add_place("voted_yes_" + k);
    PlaceId no = b.add_place("voted_no_" + k);
    b.add_output(start, voting);
    TransitionId vote_yes = b.add_transition("yes_" + k);
    b.add_input(vote_yes, voting);
    b.add_output(vote_yes, yes);
    TransitionId vote_no = b.add_transition("no_" + k);
    b.add_input(vote_no, voting);
    b.add_output(vote_no, no);
  }
  return std::move(b).build();
}

}  // namespace strata::petri
