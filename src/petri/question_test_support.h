#pragma once
// Support for the question tests (question_test.cpp,
// question_handover_test.cpp): a question parsed, options, and a witness
// replayed.
#include <gtest/gtest.h>

#include <string_view>

#include "petri/question.h"

namespace strata::petri::testing {

inline Question ask(const Net& net, std::string_view text) {
  auto q = parse_question(text, net_place_resolver(net));
  EXPECT_TRUE(q.ok()) << text << ": " << (q ? "" : q.error().message);
  return q ? std::move(q).value() : Question{};
}

inline QuestionOptions with_reduction(bool on, bool structural = true) {
  QuestionOptions o;
  o.reduction = on;
  o.structural = structural;
  return o;
}

// The witness leads from the initial marking to a marking the question
// looked for.
inline void expect_witness_replays(const Net& net, const Question& q, const QuestionResult& r) {
  ASSERT_TRUE(r.has_witness);
  const ReplayResult rep = replay(net, r.witness);
  ASSERT_TRUE(rep.complete) << rep.error;
  EXPECT_EQ(r.witness_marking, rep.marking);
  if (q.kind == QuestionKind::Deadlock) {
    EXPECT_TRUE(rep.deadlock);
  } else {
    EXPECT_TRUE(q.target.holds(rep.marking));
  }
}

}  // namespace strata::petri::testing
